"""Second held-out generator of springcad job configs (issue 25, item 8), labelled by physics.

Written without reading springcad's design code, its FEA, its tests or the first held-out
generator (bench/spec_heldout.py): only the README, templates/, springcad/config/ (keys,
ranges, defaults), springcad/data/ (materials, dowel lengths), the paper and
shared/notes/design-method.md. The specs are what a mechanical/robotics engineer would write for
a real joint, from the joint's own constraints, not from what springcad accepts.

Generator (numpy, seeded)
-------------------------
A joint: stiffness K_j log-uniform 10..2000 N*m/rad, deflection theta_j 4..30 deg. The engineer
reads that one disk reaches ~10-20 deg and picks n = ceil(theta_j / theta_disk) disks (1..6),
or (1 in 4, when theta_j / n >= 3 deg) any n from 1..6 to shrink the diameter. Identical disks
get K_i = n K_j and theta_i = theta_j / n; a mixed stack (1 in 5 of n >= 2, like the paper's
S2 + 3 x S1) has two designs A, B with K_A = r K_B (r 1.5 or 2) carrying the same torque.
Outer radius: half the time from the engineer's sizing by the paper's 0.3 J/cm^3 energy density
(x0.8..1.3), else from the package envelope (log-uniform); clipped to 12..90 mm. Thickness: a
stock plate 1.5..12 mm (4 in 5), else free, sometimes with max_thickness_mm. Material: 420_ht,
17-4ph_h900, maraging_300, ti6al4v, 7075_t6 with a safety factor, a design stress or nothing.
Dowels or bolts (ISO 4762 sizes), stack input shaft or rim, sometimes the paper's Mfr2
tolerances and a duty preset. 0..3 keys fixed per spring design from the engineer's own reasons
(n_flexures, contact_radius_mm, tip_radius_mm, min_tip_radius_mm, flexure shape, root_radius_mm)
and 0..2 hardware keys (fastener size/count, shaft diameter, rim spacer).

The physics label (written before any run)
------------------------------------------
Units: mm, N, MPa (so N*mm and mJ). Per spring design i, with T_i = K_i theta_i (the peak
torque; the same T = K_j theta_j through a series stack), sigma = design_stress_MPa, else
yield / safety_factor (1.5 if neither), E, nu, yield from the material table.

1. Torque at the tip balls (paper ref. tool eqs. 5-6, derived again): a flexure loaded at its
   ball by F = T / (N r_c) needs r_b >= 3 sqrt(3) F / (z sigma) so the ball's neck is not the
   weak section, and N balls plus N equal teeth fit the circle of r_c: N <= pi r_c / (2 r_b).
   Together T <= T_ball = pi r_c^2 z sigma / (6 sqrt 3), i.e. r_c >= r_ball = sqrt(6 sqrt3 T /
   (pi z sigma)). The hub needs r_c >= r_hub = d_shaft / 2 + 0.5 mm wall + 3 x 0.3 mm (ball and
   tooth depth). Contact (Hertz, line contact of a ball of radius r_b and length z on a flat
   flank, same material both sides, E* = E / (2 (1 - nu^2))): with N at its maximum the force
   per ball is F = 2 r_b T / (pi r_c^2), so p0^2 = F E* / (pi z r_b) = 2 T E* / (pi^2 r_c^2 z),
   independent of r_b; von Mises peak ~0.56 p0 <= yield / 1.2 gives r_hertz.
2. Rim room: a rim hole of diameter d (dowel) needs a rim width w >= d + 2 x 0.4 mm edge + 0.5
   mm root fillet; a bolt's head (ISO 4762 d_k ~ 1.5 d + 1 mm) needs w >= d_k + 0.4 + 0.5. Then
   R_r = R_o - w (or the given root_radius_mm, which must leave w). Flexure length L = R_r - r_c
   must stay >= 0.25 R_o (else no cantilever: infeasible).
3. Energy: a cantilever at uniform surface stress sigma stores at most sigma^2 / (6 E) per unit
   volume, and the flexures live in the annulus r_c..R_r of thickness z, so
   rho = (T theta / 2) / (sigma^2 / (6E) * z * pi (R_r^2 - r_c^2)), with r_c = max(r_ball, r_hub)
   or the given contact_radius_mm, z the given thickness, else max_thickness_mm, else min(R_o,
   100 mm). Reachable fill of the annulus: a straight tapered flexure fills ~(2/3) of its root
   share (<= ~0.45 in all); a serpentine fills more (paper S1: 0.64 of the annulus, area ratio
   1.24), practical limit ~0.75. Thresholds on rho: auto/serpentine <= 0.50 feasible, <= 0.75
   borderline, else infeasible; flexure = "straight" <= 0.30 / <= 0.45.
   rho_h is the same with r_c = max(r_ball, r_hub, r_hertz): rho_h > 0.75 means the balls cannot
   also meet contact yield (expect NOT FOR MANUFACTURE at most): borderline.
4. Fixed keys: a given n_flexures must fit its balls (the larger of the given/min tip radius and
   3 sqrt3 T / (N r_c z sigma)) and equal teeth on the circle r_c: N <= pi sqrt(r_b^2 + r_c^2) /
   (2 r_b); a given tip_radius_mm below 3 sqrt3 T / (N r_c z
   sigma) at the largest N that fits is undersized (warning: borderline); a given r_c below r_ball
   or r_hub is infeasible as written.
5. Pin shear for the stack torque: every rim-to-rim joint (input shaft: joints 1-2, 3-4, ...;
   input rim: 2-3, 4-5, ...) carries T on n_f pins on the hole circle R_h = R_o - w / 2, the most
   loaded 1.5 x the mean. Allowable shear: dowel 0.6 x 1600 MPa / 2 = 480 MPa on pi d^2 / 4; a
   12.9 bolt 0.6 x 1220 / 2 = 366 MPa on its minor diameter ~0.8 d. Utilisation > 1 with
   hardware written by the engineer: infeasible as written; with springcad's defaults:
   borderline (the designer may choose more pins). > 0.7: borderline.
Label: infeasible if any rule says infeasible; borderline if any says borderline; else feasible.

Harness
-------
`python bench/spec_heldout_b.py --code CHECKOUT --n 40 --seed 8 --jobs 1 --out DIR`, and beside
it or after it `... --build --max-build 16` (builds each designed spec as the design run
reports it, from the label with the fewest builds so far; DIR/builds.json) writes each spec to DIR/specs/, runs `python -m springcad design` on it with
PYTHONPATH=CHECKOUT and classifies: DESIGNED; REFUSED+NUMBERS (the message holds `key = value`;
the first is applied to a copy and design re-run: `applied -> DESIGNED` or not); REFUSED (no
numbers); CRASH (exit 3, a traceback, a signal); TIMEOUT. With --build, `springcad build` on the
designed specs (spread over labels): RELEASED, NOT FOR MANUFACTURE (reasons from build.json),
LATE FAILURE (design accepted, build failed: the message), CRASH, TIMEOUT. DIR/results.json holds
every row. `--design-only` records a refusal's first change without designing it; `--fixes` then
builds it (read by bench/heldout_fixes.py from DIR/design/<name>.log, applied to
DIR/specs/<name>_fix.toml; a build refused in its own design stage is REFUSED AT DESIGN);
`--stop-at HH:MM` starts no run that cannot end by then. Seed 2712 on main cb8e7e1 (design, build,
first change of each refusal): docs/ho12_heldout_results.md.

Measured
--------
2026-11-27, snapshot of main 48d8eda (detached worktree), seed 8, 40 specs generated; design with
--jobs 1 beside one build loop (the machine at load 18-24 on 2 cores: designs 1-275 s, builds
175-900+ s; two builds hit the first 900 s timeout, later builds run with 2400 s). State at the
last commit (the design run was still going; the closing report has the final counts):

    python bench/spec_heldout_b.py --code /tmp/snap_spec8 --n 40 --seed 8 --jobs 1 --out /tmp/spec_heldout_b
    python bench/spec_heldout_b.py --code /tmp/snap_spec8 --n 40 --seed 8 --out /tmp/spec_heldout_b --build --max-build 16 --timeout 2400
    python bench/spec_heldout_b.py --code /tmp/snap_spec8 --out /tmp/spec_heldout_b --summary
    outcome_full                              feasible  borderline  infeasible   all
    DESIGNED                                         6           1           2     9
    REFUSED                                          1           1           5     7
    REFUSED+NUMBERS, applied -> DESIGNED             2           3           6    11
    REFUSED+NUMBERS, applied -> REFUSED              4           0           4     8
    all                                             13           5          17    35

    build_outcome                             feasible  borderline  infeasible   all
    NOT FOR MANUFACTURE                              0           1           1     2
    RELEASED                                         3           0           0     3
    TIMEOUT                                          1           0           0     1
    all                                              4           1           1     6

    fix_build_outcome                         feasible  borderline  infeasible   all
    LATE FAILURE                                     0           1           0     1
    NOT FOR MANUFACTURE                              0           0           1     1
    TIMEOUT                                          1           0           0     1
    all                                              1           1           1     3

(at 02:35 UTC: 35 of 40 specs; heldout_b_020's first suggestion, `springs.S1.n_flexures removed`,
was missed by the first parser, which applied a bound from the explanation; applied by hand after,
it is refused too: "drive pin Ø2: no ISO 8734 length ... engages a 2 mm ring").

Read with care: the labels are this file's own rules, fixed before the run; where springcad
designed a spec labelled infeasible (heldout_b_027: rim and N rules applied at r_c = max(r_ball,
r_hub), while springcad chose a larger r_c) the rule, not springcad, is the weaker.
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import datetime
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

from heldout_fixes import apply_ops, describe, parse_fixes

# Material table (springcad/data/materials.csv): E GPa, nu, yield MPa.
MATERIALS = {
    "420_ht": (200.0, 0.28, 1344.0),
    "17-4ph_h900": (197.0, 0.27, 1170.0),
    "maraging_300": (190.0, 0.30, 1900.0),
    "ti6al4v": (114.0, 0.34, 880.0),
    "7075_t6": (71.7, 0.33, 503.0),
}
MATERIAL_WEIGHTS = [0.4, 0.2, 0.15, 0.17, 0.08]
PLATES_MM = [1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0]
DOWELS_MM = [1.5, 2.0, 2.5, 3.0, 4.0]
BOLTS_MM = [2.0, 2.5, 3.0, 4.0, 5.0]
DEFAULT_FASTENER_D_MM, DEFAULT_FASTENER_COUNT, DEFAULT_SHAFT_D_MM = 1.5, 7, 4.0
PAPER_ENERGY_DENSITY_MJ_PER_MM3 = 0.3  # 0.3 J/cm^3 (paper sec. IV)


def _rnd(x: float, step: float) -> float:
    return round(round(x / step) * step, 6)


# ----------------------------------------------------------------------------- generator
def _material(rng: np.random.Generator) -> dict:
    name = str(rng.choice(list(MATERIALS), p=MATERIAL_WEIGHTS))
    table = {"name": name}
    u = rng.random()
    if u < 0.4:
        table["safety_factor"] = float(rng.choice([1.2, 1.3, 1.5, 2.0]))
    elif u < 0.75:
        table["design_stress_MPa"] = _rnd(MATERIALS[name][2] * rng.uniform(0.6, 0.85), 10)
    return table


def _outer_radius_mm(rng, energy_mJ: float, thickness_mm: float) -> float:
    if rng.random() < 0.5:  # sized from the paper's energy density, with a fudge factor
        volume_mm3 = energy_mJ / PAPER_ENERGY_DENSITY_MJ_PER_MM3
        r = math.sqrt(volume_mm3 / (math.pi * thickness_mm)) * rng.uniform(0.8, 1.3)
    else:  # from the package envelope
        r = math.exp(rng.uniform(math.log(12), math.log(90)))
    return float(np.clip(_rnd(r, 0.5), 12.0, 90.0))


def _spring_extras(rng, r_o_mm: float) -> dict:
    """0..3 keys an engineer fixes for reasons of their own."""
    pool = ["n_flexures", "contact_radius_mm", "tip_radius_mm", "min_tip_radius_mm",
            "flexure", "root_radius_mm"]
    k = int(rng.choice([0, 1, 2, 3], p=[0.3, 0.3, 0.25, 0.15]))
    keys = list(rng.choice(pool, size=k, replace=False))
    out: dict = {}
    for key in keys:
        if key == "n_flexures":  # "the paper used 28", or a round number
            out[key] = int(rng.choice([12, 16, 20, 24, 28, 32, 36]))
        elif key == "contact_radius_mm":  # a hub they already have
            out[key] = _rnd(r_o_mm * rng.uniform(0.12, 0.3), 0.5)
        elif key == "tip_radius_mm":
            out[key] = float(rng.choice([0.3, 0.4, 0.5, 0.75, 1.0]))
        elif key == "min_tip_radius_mm":
            out[key] = float(rng.choice([0.3, 0.4, 0.5]))
        elif key == "flexure":
            out[key] = str(rng.choice(["straight", "serpentine"]))
        elif key == "root_radius_mm":  # rim width 2..6 mm from their housing
            out[key] = _rnd(r_o_mm - rng.uniform(2.0, 6.0), 0.5)
    if "tip_radius_mm" in out and "min_tip_radius_mm" in out:
        del out["min_tip_radius_mm"]
    return out


def generate_spec(rng: np.random.Generator, index: int) -> dict:
    """One job config (a dict of TOML tables) and its generator notes."""
    k_joint = float(np.exp(rng.uniform(math.log(10), math.log(2000))))
    k_joint = _rnd(k_joint, 5 if k_joint > 50 else 1)
    theta_joint_deg = float(_rnd(rng.uniform(4, 30), 0.5))
    n = min(6, max(1, math.ceil(theta_joint_deg / rng.uniform(10, 20))))
    if rng.random() < 0.25:
        n_alt = int(rng.integers(1, 7))
        if theta_joint_deg / n_alt >= 3.0:
            n = n_alt
    torque_Nmm = k_joint * 1000 * math.radians(theta_joint_deg)
    thickness = float(rng.choice(PLATES_MM))
    energy_mJ = 0.5 * torque_Nmm * math.radians(theta_joint_deg)
    r_o = _outer_radius_mm(rng, energy_mJ / n, thickness)
    give_thickness = rng.random() < 0.8
    mixed = n >= 2 and rng.random() < 0.2
    if mixed:
        ratio = float(rng.choice([1.5, 2.0]))
        n_b = int(rng.integers(1, n))
        n_a = n - n_b
        k_a = k_joint * (n_a + n_b * ratio)
        designs = {"A": k_a, "B": k_a / ratio}
        sequence = ["B"] * n_b + ["A"] * n_a
        rng.shuffle(sequence)
    else:
        designs = {"S1": k_joint * n}
        sequence = ["S1"] * n
    springs = {}
    for name, k in designs.items():
        theta_deg = torque_Nmm / (k * 1000) * 180 / math.pi
        spring = {"target_stiffness_Nm_per_rad": round(k, 3),
                  "max_deflection_deg": round(theta_deg, 3),
                  "outer_radius_mm": r_o}
        if give_thickness:
            spring["thickness_mm"] = thickness
        elif rng.random() < 0.5:
            spring["max_thickness_mm"] = float(rng.choice([8.0, 10.0, 12.0, 16.0, 20.0]))
        spring.update(_spring_extras(rng, r_o))
        springs[name] = spring
    hardware: dict = {}
    if rng.random() < 0.4:
        hardware["fastener"] = "bolt"
        hardware["fastener_diameter_mm"] = float(rng.choice(BOLTS_MM[:2] if r_o < 25 else BOLTS_MM))
    else:
        hardware["fastener"] = "dowel"
        if rng.random() < 0.5:
            hardware["fastener_diameter_mm"] = float(rng.choice(DOWELS_MM[:2] if r_o < 25 else DOWELS_MM))
    for key in rng.choice(["fastener_count", "shaft_diameter_mm", "rim_spacer_thickness_mm"],
                          size=int(rng.integers(0, 3)), replace=False):
        if key == "fastener_count":
            hardware[key] = int(rng.choice([3, 4, 6, 8]))
        elif key == "shaft_diameter_mm":  # their motor shaft
            hardware[key] = float(np.clip(_rnd(r_o * rng.uniform(0.08, 0.2), 1), 3, 20))
        else:
            hardware[key] = float(rng.choice([0.5, 1.0, 2.0]))
    job = {"job": {"name": f"heldout_b_{index:03d}",
                   "description": f"held-out B: {k_joint:g} N*m/rad joint over {theta_joint_deg:g} deg, {n} disk(s)"},
           "material": _material(rng), "springs": springs,
           "stack": {"sequence": sequence, "input": str(rng.choice(["shaft", "rim"], p=[0.6, 0.4]))},
           "hardware": hardware}
    if rng.random() < 0.25:
        job["manufacturing"] = {"process": "wire_edm", "t_spring_mm": 0.05, "t_shaft_mm": 0.02,
                                "w_gap_mm": 0.025}
    if rng.random() < 0.3:
        job["duty"] = {"preset": str(rng.choice(["static", "series_elastic_actuator", "prosthesis"]))}
    job["_joint"] = {"k_joint": k_joint, "theta_joint_deg": theta_joint_deg, "n": n}
    return job


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(v)


def to_toml(job: dict) -> str:
    lines = []
    for section, table in job.items():
        if section.startswith("_"):
            continue
        if section == "springs":
            for name, spring in table.items():
                lines.append(f"[springs.{name}]")
                lines += [f"{k} = {_toml_value(v)}" for k, v in spring.items()]
                lines.append("")
            continue
        lines.append(f"[{section}]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in table.items()]
        lines.append("")
    return "\n".join(lines)


# ----------------------------------------------------------------------------- physics label
def _rim_width_mm(hardware: dict) -> float:
    d = hardware.get("fastener_diameter_mm", DEFAULT_FASTENER_D_MM)
    if hardware.get("fastener", "dowel") == "bolt":
        return 1.5 * d + 1.0 + 0.4 + 0.5
    return d + 2 * 0.4 + 0.5


def _design_stress_MPa(material: dict) -> float:
    if "design_stress_MPa" in material:
        return material["design_stress_MPa"]
    return MATERIALS[material["name"]][2] / material.get("safety_factor", 1.5)


def _rim_joints(n: int, input_kind: str) -> int:
    first = 0 if input_kind == "shaft" else 1  # joint j (between j, j+1) is rim when j % 2 == first
    return sum(1 for j in range(n - 1) if j % 2 == first)


def label_spec(job: dict) -> tuple[str, list[str]]:
    """feasible / borderline / infeasible by the rules of the module docstring, with reasons."""
    mat = job["material"]
    e_MPa, nu, yield_MPa = MATERIALS[mat["name"]]
    e_MPa *= 1000
    sigma = _design_stress_MPa(mat)
    hw = job["hardware"]
    joint = job["_joint"]
    torque = joint["k_joint"] * 1000 * math.radians(joint["theta_joint_deg"])
    worst, reasons = 0, []

    def flag(level: int, text: str) -> None:
        nonlocal worst
        worst = max(worst, level)
        reasons.append(("", "borderline: ", "infeasible: ")[level] + text)

    for name, s in job["springs"].items():
        r_o = s["outer_radius_mm"]
        z = s.get("thickness_mm", s.get("max_thickness_mm", min(r_o, 100.0)))
        theta = math.radians(s["max_deflection_deg"])
        energy = 0.5 * torque * theta
        w_need = _rim_width_mm(hw)
        r_r = s.get("root_radius_mm", r_o - w_need)
        if r_o - r_r < w_need - 1e-9:
            flag(2, f"{name}: rim {r_o - r_r:.2f} mm < {w_need:.2f} mm for the fasteners")
        r_ball = math.sqrt(6 * math.sqrt(3) * torque / (math.pi * z * sigma))
        r_hub = hw.get("shaft_diameter_mm", DEFAULT_SHAFT_D_MM) / 2 + 0.5 + 0.9
        e_star = e_MPa / (2 * (1 - nu**2))
        p0_allow = yield_MPa / 1.2 / 0.56
        r_hertz = math.sqrt(2 * torque * e_star / (math.pi**2 * z * p0_allow**2))
        r_c = s.get("contact_radius_mm", max(r_ball, r_hub))
        if "contact_radius_mm" in s and r_c < max(r_ball, r_hub):
            flag(2, f"{name}: r_c {r_c} mm < {max(r_ball, r_hub):.2f} mm (balls carry T / hub)")
        if r_r - r_c < 0.25 * r_o:
            flag(2, f"{name}: flexure length {r_r - r_c:.1f} mm < 0.25 R_o")
            continue
        straight = s.get("flexure") == "straight"
        feas, border = (0.30, 0.45) if straight else (0.50, 0.75)
        cap = sigma**2 / (6 * e_MPa) * z * math.pi * (r_r**2 - r_c**2)
        rho = energy / cap
        if rho > border:
            flag(2, f"{name}: energy ratio {rho:.2f} > {border}")
        elif rho > feas:
            flag(1, f"{name}: energy ratio {rho:.2f} > {feas}")
        r_c_h = max(r_c, r_hertz)
        if r_r - r_c_h > 0:
            rho_h = energy / (sigma**2 / (6 * e_MPa) * z * math.pi * (r_r**2 - r_c_h**2))
        else:
            rho_h = math.inf
        if rho_h > 0.75 and rho <= border:
            flag(1, f"{name}: contact yield needs r_c {r_hertz:.1f} mm (energy ratio then {rho_h:.2f})")
        if torque > math.pi * r_c**2 * z * sigma / (6 * math.sqrt(3)) and "contact_radius_mm" in s:
            flag(2, f"{name}: balls at r_c {r_c} mm cannot carry T")
        if "n_flexures" in s:
            n_f = s["n_flexures"]
            r_b = max(s.get("tip_radius_mm", s.get("min_tip_radius_mm", 0.3)),
                      3 * math.sqrt(3) * torque / (n_f * r_c * z * sigma))
            if n_f > math.pi * math.hypot(r_b, r_c) / (2 * r_b):
                flag(2, f"{name}: N = {n_f} balls of {r_b:.2f} mm and teeth do not fit the circle r_c {r_c:.1f} mm")
        if "tip_radius_mm" in s:
            r_b = s["tip_radius_mm"]
            n_fit = min(s.get("n_flexures", 10**6), math.floor(math.pi * math.hypot(r_b, r_c) / (2 * r_b)))
            r_b_req = 3 * math.sqrt(3) * torque / (max(n_fit, 1) * r_c * z * sigma)
            if r_b < r_b_req:
                flag(1, f"{name}: tip ball {r_b} mm < {r_b_req:.2f} mm needed")
    n_joints = _rim_joints(len(job["stack"]["sequence"]), job["stack"]["input"])
    if n_joints:
        r_o = min(s["outer_radius_mm"] for s in job["springs"].values())
        r_h = r_o - _rim_width_mm(hw) / 2
        d = hw.get("fastener_diameter_mm", DEFAULT_FASTENER_D_MM)
        count = hw.get("fastener_count", DEFAULT_FASTENER_COUNT)
        if hw.get("fastener") == "bolt":
            area, tau = math.pi * (0.8 * d) ** 2 / 4, 0.6 * 1220 / 2
        else:
            area, tau = math.pi * d**2 / 4, 0.6 * 1600 / 2
        util = 1.5 * torque / (count * r_h) / (area * tau)
        written = "fastener_count" in hw or "fastener_diameter_mm" in hw
        if util > 1.0:
            flag(2 if written else 1, f"rim pins utilisation {util:.2f} ({count} x {d} mm)")
        elif util > 0.7:
            flag(1, f"rim pins utilisation {util:.2f}")
    return ("feasible", "borderline", "infeasible")[worst], reasons


# ----------------------------------------------------------------------------- harness
SUGGESTION = re.compile(r"(?<![x*] )\b([a-z][A-Za-z0-9_]*(?:\.[A-Za-z0-9_-]+)*)\s+=\s+"
                        r"(\"[^\"]*\"|[-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)")
REMOVED = re.compile(r"\b([a-z][A-Za-z0-9_]*(?:\.[A-Za-z0-9_-]+)*) removed")
# Bare keys a message may name without their table (README's config table).
BARE_KEYS = {"target_stiffness_Nm_per_rad", "max_deflection_deg", "max_deflection_rad",
             "outer_radius_mm", "thickness_mm", "max_thickness_mm", "contact_radius_mm",
             "min_tip_radius_mm", "tip_radius_mm", "n_flexures", "root_radius_mm", "flexure",
             "fastener", "fastener_diameter_mm", "fastener_count", "shaft_diameter_mm",
             "rim_spacer_thickness_mm", "design_stress_MPa", "safety_factor", "t_spring_mm",
             "t_shaft_mm", "w_gap_mm", "surface"}


def _is_key(name: str) -> bool:
    return name.split(".")[-1] in BARE_KEYS


def first_suggestion(text: str) -> list[tuple[str, str | None]]:
    """The first suggested change in a refusal: its `key = value` pairs (a joint change such as
    `a = 1 and b = 2, all together` or `name = x with stress = y` gives all of them; `key removed`
    gives (key, None)). Bounds such as `0.6 x outer_radius_mm = 8.1` are not suggestions."""
    found = [m for m in list(SUGGESTION.finditer(text)) + list(REMOVED.finditer(text))
             if _is_key(m.group(1))]
    if not found:
        return []
    start = min(m.start() for m in found)
    ends = [k for k in (text.find(" or ", start), text.find(";", start), text.find("(each alone", start),
                        text.find(". ", start), text.find("all together", start)) if k >= 0]
    clause = text[start:min(ends) if ends else len(text)]
    pairs = [(m.group(1), m.group(2)) for m in SUGGESTION.finditer(clause) if _is_key(m.group(1))]
    return pairs + [(m.group(1), None) for m in REMOVED.finditer(clause) if _is_key(m.group(1))]


def _run(cmd: list[str], code: Path, timeout_s: float) -> tuple[int | None, str, float]:
    env = dict(os.environ, PYTHONPATH=str(code))
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout_s, cwd=code)
        return p.returncode, (p.stdout + p.stderr), time.monotonic() - t0
    except subprocess.TimeoutExpired as exc:
        out = (exc.stdout or b"") + (exc.stderr or b"")
        return None, out.decode(errors="replace") if isinstance(out, bytes) else out, time.monotonic() - t0


def _is_crash(rc: int | None, text: str) -> bool:
    return rc is not None and (rc == 3 or rc < 0 or rc > 128 and rc not in (130, 143)
                               or "Traceback (most recent call last)" in text)


def apply_suggestion(job: dict, pairs: list[tuple[str, str | None]]) -> dict:
    """A copy of `job` with every `key = value` of `pairs` applied (value None: key removed)."""
    new = json.loads(json.dumps(job))
    for key, value in pairs:
        _apply_one(new, key, value)
    return new


def _apply_one(new: dict, key: str, value: str | None) -> None:
    """Set `key` (dotted, or a bare key: hardware, material or every spring) to `value` in place."""
    if value is None:
        parts = key.split(".")
        table = new["springs"][parts[1]] if parts[0] == "springs" else new.get(parts[0], {})
        table.pop(parts[-1], None)
        return
    val = json.loads(value) if value.startswith('"') else float(value)
    if isinstance(val, float) and val.is_integer() and (key.endswith(("count", "n_flexures"))):
        val = int(val)
    parts = key.split(".")
    if parts[0] == "springs" and len(parts) == 3:
        new["springs"][parts[1]][parts[2]] = val
    elif len(parts) == 2 and parts[0] in new["springs"]:
        new["springs"][parts[0]][parts[1]] = val
    elif len(parts) == 2:
        new.setdefault(parts[0], {})[parts[1]] = val
    elif parts[0] in {"fastener", "fastener_diameter_mm", "fastener_count", "shaft_diameter_mm",
                      "rim_spacer_thickness_mm"}:
        new["hardware"][parts[0]] = val
    elif parts[0] in {"design_stress_MPa", "safety_factor"}:
        new["material"][parts[0]] = val
    elif parts[0] in {"t_spring_mm", "t_shaft_mm", "w_gap_mm", "surface"}:
        new.setdefault("manufacturing", {})[parts[0]] = val
    else:
        for spring in new["springs"].values():
            spring[parts[0]] = val


def _last_lines(text: str, n: int = 6) -> str:
    lines = [ln for ln in text.strip().splitlines() if ln.strip()]
    return "\n".join(lines[-n:])


def design_case(job: dict, workdir: Path, code: Path, timeout_s: float,
                apply_first: bool = True) -> dict:
    """Design one spec; a refusal's first change is applied and designed unless not
    `apply_first` (then only recorded). The full output is kept in DIR/design/<name>.log."""
    name = job["job"]["name"]
    cfg = workdir / "specs" / f"{name}.toml"
    rc, text, dt = _run([sys.executable, "-m", "springcad", "design", str(cfg), "--out",
                         str(workdir / "design" / name), "--overwrite"], code, timeout_s)
    (workdir / "design").mkdir(parents=True, exist_ok=True)
    (workdir / "design" / f"{name}.log").write_text(text)
    row = {"name": name, "design_rc": rc, "design_s": round(dt, 1), "message": _last_lines(text)}
    if rc is None:
        row["outcome"] = "TIMEOUT"
    elif _is_crash(rc, text):
        row["outcome"] = "CRASH"
    elif rc == 0:
        row["outcome"] = "DESIGNED"
    else:
        pairs = first_suggestion(text)
        if not pairs:
            row["outcome"] = "REFUSED"
            return row
        row["outcome"] = "REFUSED+NUMBERS"
        row["suggestion"] = " and ".join(f"{k} = {v}" if v is not None else f"{k} removed"
                                         for k, v in pairs)
        if not apply_first:
            return row
        fixed = apply_suggestion(job, pairs)
        fixed["job"]["name"] = name + "_fix"
        fcfg = workdir / "specs" / f"{name}_fix.toml"
        fcfg.write_text(to_toml(fixed))
        rc2, text2, _ = _run([sys.executable, "-m", "springcad", "design", str(fcfg), "--out",
                              str(workdir / "design" / (name + "_fix")), "--overwrite"], code, timeout_s)
        row["applied_rc"] = rc2
        row["applied"] = ("DESIGNED" if rc2 == 0 else "CRASH" if _is_crash(rc2, text2)
                          else "TIMEOUT" if rc2 is None else "REFUSED")
        row["applied_message"] = _last_lines(text2)
    return row


def _stage(text: str) -> str:
    """The last stage a build printed it started ("[2/5] verify ..."), "design" if none."""
    found = re.findall(r"\[\d/\d\] (\w+)", text)
    return found[-1] if found else "design"


def build_case(name: str, workdir: Path, code: Path, timeout_s: float) -> dict:
    """`springcad build` of DIR/specs/<name>.toml, classified; the full output is kept in
    DIR/build/<name>.log. A non-zero exit in the design stage is "REFUSED AT DESIGN" (an
    applied change that does not design), after it "LATE FAILURE"."""
    cfg = workdir / "specs" / f"{name}.toml"
    out = workdir / "build" / name
    rc, text, dt = _run([sys.executable, "-m", "springcad", "build", str(cfg), "--out", str(out),
                         "--overwrite"], code, timeout_s)
    (workdir / "build").mkdir(parents=True, exist_ok=True)
    (workdir / "build" / f"{name}.log").write_text(text)
    row = {"build_rc": rc, "build_s": round(dt, 1), "build_message": _last_lines(text, 10),
           "stage": _stage(text)}
    if rc is None:
        row["build_outcome"] = "TIMEOUT"
    elif _is_crash(rc, text):
        row["build_outcome"] = "CRASH"
    elif rc != 0 and row["stage"] == "design":
        row["build_outcome"] = "REFUSED AT DESIGN"
    elif rc != 0:
        row["build_outcome"] = "LATE FAILURE"
    else:
        release = json.loads((out / "build.json").read_text()).get("release", {})
        released = release.get("released", release.get("status") == "RELEASED")
        row["build_outcome"] = "RELEASED" if released else "NOT FOR MANUFACTURE"
        row["release"] = release
    return row


def refusal_text(log: str) -> str:
    """The message of a refused design: springcad's `springcad <cmd>: ...` lines and what
    follows them (the progress lines before are left out)."""
    lines = log.strip().splitlines()
    first = next((i for i, ln in enumerate(lines) if re.match(r"springcad \w+: ", ln)), None)
    return "\n".join(lines[first:] if first is not None else lines[-6:])


def fix_loop(work: Path, code: Path, timeout_s: float, stop_at: float | None) -> None:
    """Build the first change each refusal of the design run names, read from its full log
    with bench/heldout_fixes.py (strict `key = value` form, disk-count changes), applied
    exactly to a copy DIR/specs/<name>_fix.toml; rows in DIR/builds.json as `<name>_fix`."""
    rows = json.loads((work / "results.json").read_text())
    out = work / "builds.json"
    for r in rows:
        if not r["outcome"].startswith("REFUSED"):
            continue
        name = r["name"]
        builds = json.loads(out.read_text()) if out.exists() else {}
        if name + "_fix" in builds:
            continue
        cfg = tomllib.loads((work / "specs" / f"{name}.toml").read_text())
        alts, note = parse_fixes(refusal_text((work / "design" / f"{name}.log").read_text()), cfg)
        row: dict = {"parser": note}
        if alts:
            timeout = _capped(timeout_s, stop_at)
            if timeout is None:
                print(f"stop before {name}_fix: too close to --stop-at", flush=True)
                return
            fixed = apply_ops(cfg, alts[0], "_fix")
            (work / "specs" / f"{name}_fix.toml").write_text(to_toml(fixed))
            row["change"] = describe(alts[0])
            row.update(build_case(name + "_fix", work, code, timeout))
        else:
            row["build_outcome"] = "NO CHANGE PARSED"
        builds = json.loads(out.read_text()) if out.exists() else {}
        builds[name + "_fix"] = row
        out.write_text(json.dumps(builds, indent=1))
        print(f"{name}_fix  {row.get('change', '-')}  {row['build_outcome']}"
              f"  {row.get('build_s', '')} s", flush=True)


def _capped(timeout_s: float, stop_at: float | None, least_s: float = 60.0) -> float | None:
    """`timeout_s`, cut so the run ends by `stop_at` (epoch s); None if under `least_s` is left."""
    if stop_at is None:
        return timeout_s
    left = stop_at - time.time()
    return None if left < least_s else min(timeout_s, left)


def _candidates(rows: list[dict]) -> dict:
    """Buildable configs and their group: each designed spec under its label, and each applied
    suggestion that designed (`<name>_fix`) under "suggested fix"."""
    out = {r["name"]: r["label"] for r in rows if r["outcome"] == "DESIGNED"}
    out.update({r["name"] + "_fix": "suggested fix" for r in rows if r.get("applied") == "DESIGNED"})
    return out


def _next_build(rows: list[dict], builds: dict, limit: int) -> str | None:
    """The next config to build: from the group with the fewest builds so far."""
    if sum(1 for v in builds.values() if v.get("build_outcome") != "claimed") >= limit:
        return None
    cands = _candidates(rows)
    done = {g: sum(1 for n in builds if cands.get(n) == g)
            for g in ("feasible", "borderline", "infeasible", "suggested fix")}
    waiting = sorted((done[g], n) for n, g in cands.items() if n not in builds)
    return waiting[0][1] if waiting else None


def labels_of(rows: list[dict]) -> dict:
    return {**{r["name"]: r["label"] for r in rows}, **_candidates(rows)}


def build_loop(work: Path, code: Path, n_specs: int, limit: int, timeout_s: float,
               stop_at: float | None = None) -> None:
    """Build designed specs as the design run (possibly still going) reports them."""
    results, out = work / "results.json", work / "builds.json"
    builds = json.loads(out.read_text()) if out.exists() else {}
    while True:
        rows = json.loads(results.read_text()) if results.exists() else []
        done = json.loads(out.read_text()) if out.exists() else {}
        builds = {**{k: v for k, v in builds.items() if v.get("build_outcome") == "claimed"}, **done}
        name = _next_build(rows, builds, limit)
        if name is None:
            if len(rows) >= n_specs or len(builds) >= limit:
                return
            time.sleep(20)
            continue
        timeout = _capped(timeout_s, stop_at)
        if timeout is None:
            print(f"stop before {name}: too close to --stop-at", flush=True)
            return
        try:  # a claim, so that two build loops share the work
            os.close(os.open(work / "specs" / f"{name}.claim", os.O_CREAT | os.O_EXCL))
        except FileExistsError:
            builds[name] = {"build_outcome": "claimed"}
            continue
        row = build_case(name, work, code, timeout)
        builds = json.loads(out.read_text()) if out.exists() else {}
        builds[name] = row
        out.write_text(json.dumps(builds, indent=1))
        print(f"{name}  {labels_of(rows)[name]:10s}  {builds[name]['build_outcome']}"
              f"  {builds[name]['build_s']} s", flush=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--code", type=Path, required=True, help="springcad checkout (PYTHONPATH)")
    ap.add_argument("--out", type=Path, default=Path("/tmp/spec_heldout_b"))
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--seed", type=int, default=8)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=600.0, help="per run, s")
    ap.add_argument("--build", action="store_true", help="build the designed specs (reads results.json)")
    ap.add_argument("--max-build", type=int, default=16)
    ap.add_argument("--summary", action="store_true", help="only print the tables of DIR")
    ap.add_argument("--fixes", action="store_true",
                    help="build the first change each refusal names (bench/heldout_fixes.py)")
    ap.add_argument("--stop-at", help="HH:MM UTC: start no run that cannot end by then")
    ap.add_argument("--design-only", action="store_true",
                    help="design every spec; record a refusal's first change, do not design it")
    args = ap.parse_args(argv)
    code, work = args.code.resolve(), args.out.resolve()
    (work / "specs").mkdir(parents=True, exist_ok=True)
    results = work / "results.json"
    if args.summary:
        _print_counts(json.loads(results.read_text()), work)
        return 0
    stop_at = None
    if args.stop_at:
        hh, mm = (int(x) for x in args.stop_at.split(":"))
        now = datetime.datetime.now(datetime.timezone.utc)
        stop_at = now.replace(hour=hh, minute=mm, second=0, microsecond=0).timestamp()
    if args.build or args.fixes:
        if args.build:
            build_loop(work, code, args.n, args.max_build, args.timeout, stop_at)
        if args.fixes:
            fix_loop(work, code, args.timeout, stop_at)
        rows = json.loads(results.read_text())
    else:
        rng = np.random.default_rng(args.seed)
        jobs = [generate_spec(rng, i) for i in range(args.n)]
        rows = json.loads(results.read_text()) if results.exists() else []  # resume
        done = {r["name"] for r in rows}
        for job in jobs:
            (work / "specs" / f"{job['job']['name']}.toml").write_text(to_toml(job))
        jobs = [j for j in jobs if j["job"]["name"] not in done]
        with cf.ThreadPoolExecutor(args.jobs) as pool:
            futs = {pool.submit(design_case, j, work, code, args.timeout, not args.design_only): j
                    for j in jobs}
            for fut in cf.as_completed(futs):
                job = futs[fut]
                row = fut.result()
                row["label"], row["label_reasons"] = label_spec(job)
                rows.append(row)
                print(f"{row['name']}  {row['label']:10s}  {row['outcome']}  {row.get('applied', '')}"
                      f"  {row['design_s']} s", flush=True)
                rows.sort(key=lambda r: r["name"])
                results.write_text(json.dumps(rows, indent=1))
    _print_counts(rows, work)
    return 0


def _print_counts(rows: list[dict], work: Path) -> None:
    """Outcome counts, and label x outcome tables for design and build."""
    from collections import Counter
    builds = json.loads((work / "builds.json").read_text()) if (work / "builds.json").exists() else {}
    fixes = {n[:-4]: b for n, b in builds.items() if n.endswith("_fix")}
    for r in rows:
        r.update(builds.get(r["name"], {}))
        if r["name"] in fixes:
            r["fix_build_outcome"] = fixes[r["name"]]["build_outcome"]
        if r["outcome"] == "REFUSED+NUMBERS":
            r["outcome_full"] = f"REFUSED+NUMBERS, applied -> {r.get('applied')}"
        else:
            r["outcome_full"] = r["outcome"]
    labels = ("feasible", "borderline", "infeasible")
    for field in ("outcome_full", "build_outcome", "fix_build_outcome"):
        seen = sorted({r[field] for r in rows if field in r})
        if not seen:
            continue
        print(f"\n{field:38s}" + "".join(f"{lab:>12s}" for lab in labels) + f"{'all':>6s}")
        count = Counter((r[field], r["label"]) for r in rows if field in r)
        for out in seen:
            print(f"{out:38s}" + "".join(f"{count[(out, lab)]:12d}" for lab in labels)
                  + f"{sum(count[(out, lab)] for lab in labels):6d}")
        print(f"{'all':38s}" + "".join(f"{sum(count[(o, lab)] for o in seen):12d}" for lab in labels)
              + f"{sum(count.values()):6d}")


if __name__ == "__main__":
    sys.exit(main())
