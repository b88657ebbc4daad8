"""Every check of a built stack, with its measured value and verdict.

Two kinds of check:

* ``error``: the geometry is wrong (invalid solid, volume off its profile,
  parts overlapping or touching where they should not, a cam-to-tip gap other
  than designed, a connection sequence against the paper's alternation rule).
  A build with one of these always fails.
* ``rule``: a manufacturability rule of the part's process: wire EDM from
  ``[manufacturing]`` (:mod:`springcad.geometry.edm`), laser-cut and milled sheet
  from ``springcad/data/processes.toml`` (:mod:`springcad.geometry.sheet_cut`), and
  for every made part the fits its process can finish. A violation fails the build
  unless the user explicitly accepts violations.

Units: mm, mm^3.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field

from springcad.cache import memo
from springcad.connections import connection_sequence
from springcad.design.cam import GAP_RESOLUTION_MM
from springcad.errors import CheckFailed, GeometryError
from springcad.geometry.edm import edm_rules
from springcad.geometry.interference import InterferenceChecker, cam_clearance
from springcad.geometry.sheet_cut import (fit_rule, internal_profile_rule, sheet_rules,
                                          sheet_stock_rules, wall_rule)
from springcad.geometry.stack import build_stack
from springcad.options import spell
from springcad.progress import Progress, Tracker, no_progress
from springcad.stages import stage

#: measured cam-to-tip clearance must equal the designed gap within this (mm): the
#: kernel's spline edges match the design curves to ~1 um; the design's rule uses the same
CLEARANCE_TOL_MM = GAP_RESOLUTION_MM
#: solid volume against slab area x length (relative): the exact divergence volume
#: agrees to ~1e-7; the sampled profile area to ~1e-5
VOLUME_RTOL = 1e-4

#: kind pairs that are meant to touch (faces along the axis or fits around it)
MEANT_TO_TOUCH = {frozenset(p) for p in (
    ("flexure_ring", "rim_spacer"), ("flexure_ring", "rim_washer"),
    ("flexure_ring", "centre_spacer"), ("flexure_ring", "rim_flange"),
    ("flexure_ring", "fastener"), ("fastener", "rim_spacer"), ("fastener", "rim_washer"),
    ("fastener", "rim_flange"), ("fastener", "fastener"),
    ("camshaft", "centre_spacer"), ("camshaft", "alignment_shaft"),
    ("camshaft", "torque_shaft"), ("centre_spacer", "alignment_shaft"),
)}


@dataclass
class Check:
    """One check and its result.

    Attributes:
        name: check name, e.g. ``"solid_valid"``, ``"edm.min_web"``.
        subject: what was checked (part number, instance names, "stack").
        passed: the verdict.
        kind: "error" or "rule" (see the module docstring).
        value: measured value (unit in ``unit``), if any.
        limit: the limit or design value it was held against.
        unit: unit of value and limit.
        message: one line for humans.
        details: violations with locations, per-sector values, ...
    """

    name: str
    subject: str
    passed: bool
    kind: str = "error"
    value: float | None = None
    limit: float | None = None
    unit: str = "mm"
    message: str = ""
    details: list = field(default_factory=list)

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass
class CheckReport:
    """All checks of one build."""

    checks: list[Check]

    @property
    def errors(self) -> list[Check]:
        return [c for c in self.checks if c.kind == "error" and not c.passed]

    @property
    def violations(self) -> list[Check]:
        return [c for c in self.checks if c.kind == "rule" and not c.passed]

    def passed(self, accept_violations: bool = False) -> bool:
        return not self.errors and (accept_violations or not self.violations)

    def summary(self) -> str:
        n_err, n_rule = len(self.errors), len(self.violations)
        return (f"{len(self.checks)} checks: {len(self.checks) - n_err - n_rule} passed, "
                f"{n_err} geometry errors, {n_rule} manufacturability violations")

    def to_dict(self) -> dict:
        return {"summary": self.summary(), "checks": [c.to_dict() for c in self.checks]}

    def raise_if_failed(self, accept_violations: bool = False) -> None:
        """Raise :class:`ChecksFailed` unless the build may go on."""
        if not self.passed(accept_violations):
            raise ChecksFailed(self, accept_violations)


class ChecksFailed(CheckFailed):
    """A build failed its checks; ``report`` holds every check (a :class:`CheckFailed`)."""

    def __init__(self, report: CheckReport, accept_violations: bool):
        self.report = report
        lines = [report.summary()]
        for c in report.errors + ([] if accept_violations else report.violations):
            lines.append(f"  {c.subject}: {c.name}: {c.message}")
            for v in c.details[:3] if c.kind == "rule" else ():
                lines.append(f"    {v.get('value_mm', 0):.4f} mm at {v.get('feature', '')} "
                             f"(x {v['x_mm']:.3f}, y {v['y_mm']:.3f})")
            if c.kind == "rule" and len(c.details) > 3:
                lines.append(f"    ... {len(c.details) - 3} more")
        if report.violations and not report.errors and not accept_violations:
            lines.append(f"change the design or pass {spell('accept_violations', True)} to build "
                         "anyway")
        super().__init__("\n".join(lines))


# --------------------------------------------------------------------------- part checks
def _rule_checks(prefix: str, pn: str, results) -> list[Check]:
    """One rule check per result (and one for its notes, if any)."""
    out = []
    for res in results:
        if res.rule == "fits":
            msg = ("every fit is one the process finishes" if res.passed else
                   "; ".join(v["feature"] for v in res.violations))
            out.append(Check(f"{prefix}.fits", pn, res.passed, "rule", None, None, "", msg,
                             list(res.violations)))
            continue
        if res.value_mm is None:
            msg = (f"nothing below {res.searched_to_mm:g} mm" if res.searched_to_mm
                   else "no feature of this kind")
        else:
            msg = f"smallest {res.value_mm:.4f} mm, limit {res.limit_mm:g} mm"
        if res.loss_mm and (res.value_mm is not None or res.searched_to_mm):
            msg += (f" (worst case: the nominal profile's {res.loss_mm:g} mm less, the "
                    "tolerances' share)")
        if res.violations:
            msg += f"; {len(res.violations)} violation(s)"
        out.append(Check(f"{prefix}.{res.rule}", pn, res.passed, "rule", res.value_mm,
                         res.limit_mm, "mm", msg, list(res.violations)))
        if res.notes:
            out.append(Check(f"{prefix}.{res.rule}.notes", pn, True, "rule", None, None, "",
                             f"{len(res.notes)} joins are not tangent but leave less than "
                             "a tenth of the profile tolerance uncut", list(res.notes)))
    return out


def part_checks(part, manufacturing=None) -> list[Check]:
    """Validity, volume against its 2D description, and the rules of its process.

    Every made part: its ISO fits are ones its process finishes (``<process>.fits``).
    Wire-EDM profiles: the ``[manufacturing]`` rules (:mod:`springcad.geometry.edm`), from
    the part's own spring or else ``manufacturing``; cut from sheet stock (a shim), webs
    and hole edges at least the sheet thickness too (``edm.sheet_web``,
    ``edm.sheet_hole_edge``). Laser-cut and milled sheet profiles:
    the process's web, hole-edge and hole-size rules (:mod:`springcad.geometry.sheet_cut`).
    Turned parts, and cut parts with a turned section (an end camshaft's hub): the wall
    between bore or socket and outer diameter (``turned.min_wall``). Every made part with
    a non-round hole or pocket: the process of its chain that makes it
    (``<maker>.internal_profile``, e.g. ``sinker_edm.internal_profile`` for a blind D
    socket).
    """
    pn = part.part_number
    valid = getattr(part, "solid_valid", None)  # the kernel's answer when building asked it
    valid = bool(part.solid.is_valid) if valid is None else valid
    out = [Check("solid_valid", pn, valid, unit="",
                 message="valid solid" if valid else "the kernel reports an invalid solid")]
    if part.exact_prism:
        v, ref = part.volume_mm3(), part.slab_volume_mm3()
        ok = abs(v - ref) <= VOLUME_RTOL * ref
        out.append(Check("volume_matches_profile", pn, ok, value=v, limit=ref, unit="mm^3",
                         message=f"solid {v:.3f} mm^3 vs profile area x length {ref:.3f} mm^3 "
                                 f"({100 * (v / ref - 1):+.4f} %)"))
    info = part.info
    if info.process == "purchased":
        return out
    results = [fit_rule(info)]
    if info.cut_profile is not None:
        if info.process == "wire_edm":
            spring = getattr(part, "spring", None)
            mfg = spring.manufacturing if spring is not None else manufacturing
            if mfg is None:
                raise GeometryError(f"{pn}: a wire-EDM part needs the job's [manufacturing] "
                                    "rules to be checked")
            results += edm_rules(info.cut_profile, mfg, part.tolerance_mm, part.describe)
            results += sheet_stock_rules(info.cut_profile, info.thickness_mm, mfg,
                                         part.describe)
        else:
            results += sheet_rules(info.cut_profile, info.process, info.thickness_mm,
                                   part.describe)
    elif info.process == "turned":
        results.append(wall_rule(part.slabs, "turned", part.describe))
    prefix = "edm" if info.process == "wire_edm" else info.process
    out += _rule_checks(prefix, pn, results)
    spring = getattr(part, "spring", None)
    mfg = spring.manufacturing if spring is not None else manufacturing
    maker, internal = internal_profile_rule(
        info, part.slabs, mfg.min_inside_radius_mm if mfg is not None else None, part.describe)
    if internal.value_mm is not None or internal.violations:
        out += _rule_checks(maker, pn, [internal])
    if info.process != "turned" and "turned" in info.secondary_processes:
        # a cut part with a turned section (an end camshaft's hub): the walls of its
        # sections that are not the cut profile, as turned
        turned = [sl for sl in part.slabs if sl.region is not info.cut_profile]
        out += _rule_checks("turned", pn, [wall_rule(turned, "turned", part.describe)])
    return out


# ----------------------------------------------------------------------- assembly checks
def interference_checks(assembly) -> list[Check]:
    """Every pair that overlaps, or touches although not meant to, fails."""
    out = []
    kinds = {i.name: i.component.kind for i in assembly.instances}
    contacts = 0
    for r in InterferenceChecker(assembly).all_pairs():
        subject = f"{r.a} / {r.b}"
        if r.relation == "overlap":
            out.append(Check("interference", subject, False, value=r.depth_mm, limit=0.0,
                             message=f"parts overlap by {r.depth_mm:.4f} mm",
                             details=[{"x_mm": r.location[0], "y_mm": r.location[1],
                                       "z_mm": r.location[2]}]))
        elif r.relation != "clear":
            contacts += 1
            meant = frozenset((kinds[r.a], kinds[r.b])) in MEANT_TO_TOUCH
            if not meant:
                out.append(Check("unintended_contact", subject, False, value=0.0,
                                 message=f"{r.relation.replace('_', ' ')} between a "
                                         f"{kinds[r.a]} and a {kinds[r.b]}",
                                 details=[{"x_mm": r.location[0], "y_mm": r.location[1],
                                           "z_mm": r.location[2]}]))
    n = len(assembly.instances)
    if not out:
        out.append(Check("interference", "stack", True, value=0.0, limit=0.0,
                         message=f"{n * (n - 1) // 2} part pairs: no overlaps, "
                                 f"{contacts} contacts, all where parts are meant to touch"))
    return out


def _shares_z(a, b, tol=1e-6) -> bool:
    return min(a.z_range_mm[1], b.z_range_mm[1]) - max(a.z_range_mm[0], b.z_range_mm[0]) > tol


def clearance_checks(assembly) -> list[Check]:
    """Measured cam-to-tip gap of every ring against its camshaft equals the design gap."""
    rings = [i for i in assembly.instances if i.component.kind == "flexure_ring"]
    cams = [i for i in assembly.instances if i.component.kind == "camshaft"]
    cache: dict = {}
    samples: dict = {}  # the tip loops' samples, shared by rings (camshafts) of one part
    out = []
    for ring in rings:
        engaged = [c for c in cams if _shares_z(ring, c)]
        if len(engaged) != 1:
            out.append(Check("cam_clearance", ring.name, False,
                             message=f"engaged by {len(engaged)} camshafts, expected 1"))
            continue
        cam = engaged[0]
        # identical parts in identical relative placement measure identically
        key = (ring.part.part_number, cam.part.part_number, cam.placement.flipped,
               cam.placement.angle_rad - ring.placement.angle_rad)
        if key not in cache:
            cache[key] = cam_clearance(ring, cam, samples=samples)
        res = cache[key]
        gap = res.design_gap_mm
        ok = (abs(res.kernel_min_mm - gap) <= CLEARANCE_TOL_MM
              and abs(res.sampled_min_mm - gap) <= CLEARANCE_TOL_MM)
        out.append(Check(
            "cam_clearance", f"{ring.name} / {cam.name}", ok, value=res.kernel_min_mm, limit=gap,
            message=f"min gap {res.kernel_min_mm:.5f} mm (B-rep) / {res.sampled_min_mm:.5f} mm "
                    f"(all {ring.part.n_flexures} flexures, at flexure {res.sampled_flexure}); "
                    f"design {gap:g} mm",
            details=[{"flexure": k, "gap_mm": v} for k, v in res.kernel_by_flexure.items()]))
    return out


def connection_checks(assembly) -> list[Check]:
    """The placed parts realise the design's connection sequence (paper Section II-A).

    Joints are read from the geometry: two consecutive rings share a rim when a
    fastener passes through both, a shaft when one camshaft engages both; joints
    must alternate, and the input and output parts must be the first and last
    spring's camshaft or rim as the sequence says.
    """
    stack = assembly.design.stack
    inst = assembly.instances
    rings = sorted((i for i in inst if i.component.kind == "flexure_ring"),
                   key=lambda i: i.z_range_mm[0])
    cams = [i for i in inst if i.component.kind == "camshaft"]
    fasteners = [i for i in inst if i.component.kind == "fastener"]
    out = []
    seen = []
    for a, b in zip(rings, rings[1:]):
        shaft = any(_shares_z(c, a) and _shares_z(c, b) for c in cams)
        rim = any(_shares_z(f, a) and _shares_z(f, b) for f in fasteners)
        seen.append("shaft" if shaft and not rim else "rim" if rim and not shaft else "invalid")
    rule_joints, rule_output = connection_sequence(len(rings), stack.input)
    ok = seen == list(stack.joints) == list(rule_joints)
    out.append(Check("connection_sequence", "stack", ok, unit="",
                     message=f"joints from geometry {seen or ['none']}, design "
                             f"{list(stack.joints) or ['none']}"
                             + ("" if ok else ": joints must alternate rim/shaft")))
    for end, ring, conn in (("input", rings[0], stack.input), ("output", rings[-1], stack.output)):
        names = {i.name for i in inst if i.role == end}
        if conn == "shaft":
            cam = [c for c in cams if _shares_z(c, ring)]
            good = bool(cam) and cam[0].name in names and ring.name not in names
            what = f"camshaft {cam[0].name if cam else '?'}"
        else:
            good = ring.name in names and not any(c.name in names for c in cams)
            what = f"rim of {ring.name}"
        out.append(Check(f"{end}_connection", "stack", good, unit="",
                         message=f"{end} through the {what} ({conn}); parts with role "
                                 f"{end}: {sorted(names)}"))
    n = len(rings)
    rule = stack.output == rule_output
    out.append(Check("alternation_rule", "stack", rule, unit="",
                     message=f"{n} spring(s): input {stack.input}, output {stack.output} "
                             f"(output {rule_output} expected)"))
    if stack.layout.floating_camshafts:
        kinds = {i.component.kind for i in inst}
        good = {"bushing", "alignment_shaft"} <= kinds
        out.append(Check("alignment_parts", "stack", good, unit="",
                         message="outer bushing and alignment shaft present" if good else
                         "three or more springs need an outer bushing and an alignment shaft"))
    return out


def run_checks(assembly, progress: Progress = no_progress) -> CheckReport:
    """Run every check on a built stack.

    Args:
        assembly: a :class:`~springcad.geometry.stack.StackAssembly`.
        progress: ``progress(message, fraction=None)``, called per step.
    """
    checks: list[Check] = []
    steps = len(assembly.parts) + 2
    for k, part in enumerate(assembly.parts.values()):
        progress(f"checking {part.part_number}", k / steps)
        checks += part_checks(part, assembly.design.stack.springs[0].manufacturing)
    progress("checking interference", (steps - 2) / steps)
    checks += interference_checks(assembly)
    progress("measuring cam-to-tip clearance", (steps - 1) / steps)
    checks += clearance_checks(assembly)
    checks += connection_checks(assembly)
    return CheckReport(checks)


def build_and_check(job_design, progress: Progress | None = None, cache=None):
    """The build stage of every door: the solids of every part, then every check.

    ``sc.build`` and the synthesis finalists both run it. A CAD-kernel failure becomes a
    :class:`~springcad.errors.StageError` naming the stage ("solids" or "checks") and the
    part being worked on.

    Args:
        job_design: a :class:`~springcad.design.job.JobDesign`.
        progress: optional ``progress(message, fraction=None)``.
        cache: a :class:`springcad.cache.Cache` holding the checks of designs checked
            before (the solids are a function of the design, so are their checks), or None.

    Returns:
        ``(assembly, report, timings_s)``: the
        :class:`~springcad.geometry.stack.StackAssembly` (mm), its :class:`CheckReport`
        and the seconds each of the two steps took.
    """
    track = Tracker(progress)
    timings = {}
    t0 = time.perf_counter()
    with stage("solids", track.subject("solids")):
        assembly = build_stack(job_design, progress=track)
    timings["solids"] = round(time.perf_counter() - t0, 3)
    t0 = time.perf_counter()
    track.last = ""
    with stage("checks", track.subject("checks")):
        report = memo(cache, "checks", (job_design,), lambda: run_checks(assembly, progress=track),
                      lambda: track("checks of this design from the cache"))
    timings["checks"] = round(time.perf_counter() - t0, 3)
    return assembly, report, timings
