"""Springs sharing a camshaft (shaft-to-shaft joints) designed on one layout.

A shared camshaft has one tooth profile, so its springs must share N, the contact radius
r_c and the tip ball (the gap ``w_gap_mm`` is the job's). Checked and searched at design
time, in milliseconds to seconds, instead of found by the solids' checks after the FEA.
Units: mm.
"""

from __future__ import annotations

import math
from dataclasses import replace

from springcad.config import Job, SpringSpec
from springcad.design.connections import camshaft_indices, connection_sequence
from springcad.design.shortfalls import margin_shortfall, soft_shortfalls
from springcad.design.spring import SpringDesign
from springcad.design.stock import design_spring
from springcad.errors import DesignError


def camshaft_groups(job: Job) -> list[tuple[str, ...]]:
    """Names of the distinct springs that share a camshaft (shaft-to-shaft joints), per shaft
    with more than one distinct spring. A shared camshaft has one tooth profile, so its
    springs must share N, r_c and the tip ball (the gap ``w_gap_mm`` is the job's)."""
    seq = job.stack.sequence
    joints, _ = connection_sequence(len(seq), job.stack.input)
    cams = camshaft_indices(joints)
    groups = {}
    for name, cam in zip(seq, cams):
        groups.setdefault(cam, [])
        if name not in groups[cam]:
            groups[cam].append(name)
    return [tuple(g) for g in groups.values() if len(g) > 1]


def _cam_key(d: SpringDesign) -> tuple:
    return (d.n_flexures, round(d.contact_radius_mm, 9), round(d.tip_radius_mm, 9))


#: the layout keys springs sharing a camshaft must share (one tooth profile)
CAMSHAFT_KEYS = ("n_flexures", "contact_radius_mm", "tip_radius_mm")


def _pinned(spec: SpringSpec, fixed: dict) -> SpringSpec:
    """``spec`` with the shared camshaft's layout ``fixed``, the keys the user left free
    marked as springcad's (``shared_camshaft``: a refusal never asks to remove them)."""
    return replace(spec, **fixed, shared_camshaft=tuple(
        k for k in CAMSHAFT_KEYS if getattr(spec, k) is None))


def share_camshafts(job: Job, springs: dict[str, SpringDesign],
                     max_root_radius_mm: float = math.inf, explain: bool = True
                     ) -> dict[str, SpringDesign]:
    """Springs sharing a camshaft redesigned on one layout (N, r_c, tip ball).

    The shared layouts tried (:func:`_shared_layouts`): each member's own layout, with the
    largest ball of the group (so every member's tip load is carried), then each member's
    design with that ball fixed; the other members are redesigned with the three fixed,
    and the first layout that designs every member wins. Milliseconds to seconds, at design
    time, instead of a conflict found by the solids' checks after the FEA.

    Raises:
        DesignError: no layout suits every member: names the springs, each try, and (with
            ``explain``) the user's own camshaft key whose removal lets them share one.
    """
    out = dict(springs)
    for group in camshaft_groups(job):
        if len({_cam_key(out[n]) for n in group}) == 1:
            continue
        tries, kept = [], None
        for leader, fixed in _shared_layouts(job, group, out, max_root_radius_mm):
            try:
                redone = {n: design_spring(_pinned(job.springs[n], fixed), job.material,
                                           job.manufacturing, job.hardware, explain=False,
                                           max_root_radius_mm=max_root_radius_mm)
                          for n in group}
            except DesignError as err:
                tries.append(f"{leader}'s N = {fixed['n_flexures']}, r_c = "
                             f"{fixed['contact_radius_mm']:.3f} mm, tip "
                             f"{fixed['tip_radius_mm']:.3f} mm: {err}")
                continue
            kept = kept or redone
            if not any(_short(d) for d in redone.values()):
                kept = redone
                break
        if kept is not None:  # the first layout every member carries clean, else the first
            for n, d in kept.items():
                out[n] = replace(d, design_choice=(
                    f"{d.design_choice}; N, r_c and tip ball shared with "
                    f"{', '.join(m for m in group if m != n)} (one camshaft)"))
        else:
            freed = _freed_camshaft_key(job, group, out, max_root_radius_mm) if explain else ""
            raise DesignError(
                f"springs {', '.join(group)} share a camshaft, so they need one N, contact "
                f"radius and tip ball, and no member's layout suits the others: "
                + "; ".join(tries) + (f"; feasible with {freed}" if freed else
                                      "; give them the same n_flexures, contact_radius_mm and "
                                      "tip_radius_mm that one of them can carry, or similar "
                                      "stiffness and envelope"))
    return out


def _short(d: SpringDesign) -> bool:
    """Whether a member designed on a shared layout falls short of a soft rule or of its
    yield margin (the search then kept its best layout, warned): another shared layout
    may carry it clean (a layout whose root fillets, lowered to fit, leave the margin 1.46
    against 1.5 came before one that keeps it)."""
    return bool(soft_shortfalls(d) or margin_shortfall(d, d.required_yield_margin))


def _shared_layouts(job: Job, group: tuple[str, ...], designs: dict[str, SpringDesign],
                    max_root_radius_mm: float):
    """``(member, fixed keys)`` of the layouts a camshaft shared by ``group`` is tried on,
    each once: every member's own layout with the group's largest ball, then every
    member's design with that ball fixed (held-out B 9041 006: B's own N = 15 at r_c 5.5
    mm had room for 11 of A's 0.75 mm balls; B designed with that ball picks a layout
    that has room)."""
    tip = max(designs[n].tip_radius_mm for n in group)
    seen = set()

    def fixed_of(d: SpringDesign) -> dict:
        return dict(n_flexures=d.n_flexures, contact_radius_mm=d.contact_radius_mm,
                    tip_radius_mm=tip, min_tip_radius_mm=min(tip, d.spec.min_tip_radius_mm))

    for leader in group:
        d = designs[leader]
        key = (d.n_flexures, round(d.contact_radius_mm, 9), round(tip, 9))
        if key not in seen:
            seen.add(key)
            yield leader, fixed_of(designs[leader])
    for leader in group:
        if abs(designs[leader].tip_radius_mm - tip) < 1e-9:
            continue  # its own layout already carries the group's ball
        spec = job.springs[leader]
        try:
            d = design_spring(replace(spec, tip_radius_mm=tip,
                                      min_tip_radius_mm=min(tip, spec.min_tip_radius_mm)),
                              job.material, job.manufacturing, job.hardware, explain=False,
                              max_root_radius_mm=max_root_radius_mm)
        except DesignError:
            continue
        if _cam_key(d) not in seen:
            seen.add(_cam_key(d))
            yield leader, fixed_of(d)


def _freed_camshaft_key(job: Job, group: tuple[str, ...], designs: dict[str, SpringDesign],
                        max_root_radius_mm: float) -> str:
    """The first camshaft key a member's config fixes (:data:`CAMSHAFT_KEYS`) whose removal
    lets the group share a camshaft, as a refusal's change ("springs.A.tip_radius_mm removed
    (now 0.75 mm)"), or "". Only the freed member is designed again; the others keep
    their ``designs``."""
    for name in group:
        spec = job.springs[name]
        for key in CAMSHAFT_KEYS:
            if getattr(spec, key) is None or key in spec.shared_camshaft:
                continue
            freed = replace(job, springs={**job.springs, name: replace(spec, **{key: None})})
            try:
                alone = {**designs, name: design_spring(
                    freed.springs[name], job.material, job.manufacturing, job.hardware,
                    explain=False, max_root_radius_mm=max_root_radius_mm)}
                share_camshafts(freed, alone, max_root_radius_mm, explain=False)
            except DesignError:
                continue
            unit = "" if key == "n_flexures" else " mm"
            return f"springs.{name}.{key} removed (now {getattr(spec, key):g}{unit})"
    return ""
