"""Evaluate a batch of candidate stacks: screened disks -> stack metrics and constraints.

:func:`evaluate_batch` is the Dask task: it decodes candidate ids, screens each
distinct disk once (:func:`~springcad.synthesis.screening.screen_disks`; the A
design of a mixed family recurs for every B thickness and both inputs), and
assembles the stack: series stiffness and eq. 10 hold by construction (every disk
designed for the same peak torque), mass from the stack hardware rules of
:func:`springcad.design.hardware.stack_layout` fed with the screened disks,
axial length and envelope radius, the predicted peak stress and its yield and fatigue
margins (each disk screened with the design's stress passes), nominal and worst-case
backlash (eqs. 1-3), energy density and specific energy, EDM cut length.

The first failed check is the binding constraint; its ``value`` and ``limit``
(and ``violation`` = how far past the limit, as a fraction) travel with the row so
the report can say by how much a family misses. Units: N*mm, mm, rad, MPa, kg, J.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from springcad.config import MaterialSpec
from springcad.design.catalogue import MIN_ENGAGEMENT_PER_DIAMETER
from springcad.design.hardware import BUSHING_CLEARANCE_MM, stack_layout
from springcad.connections import connection_sequence
from springcad.design.connections import RIM, camshaft_indices
from springcad.design.tolerance import backlash_rad, gap_range_mm
from springcad.errors import DesignError
from springcad.synthesis.screening import REASONS, screen_disks
from springcad.units import J_PER_NMM, MM3_PER_CM3, NMM_PER_NM

#: stack-level constraints after the disk ones
HOLES, AXIAL, RADIAL, STIFFNESS = "rim_holes", "axial_length", "envelope_radius", "stiffness"
#: the rim joints' hardware cannot be laid out (no catalogue dowel fits the two rims)
DOWELS = "rim_dowels"
#: constraints where a smaller value is the violation (value/limit < 1 fails)
_SMALLER_BAD = {"root_gap", "cam_tooth", "cam_bore", "serpentine_shape", HOLES, DOWELS}
#: what a failed check at the lowered beam stress means in the report
_REGIONS = ("flexure flank", "root fillet", "tip-neck fillet")


@dataclass(frozen=True)
class _Disk:
    """The attributes of a SpringDesign that stack_layout reads, from the screening."""

    name: str
    thickness_mm: float
    outer_radius_mm: float
    root_radius_mm: float
    profile_area_mm2: float
    cam_area_mm2: float
    cam_tip_radius_mm: float
    cam_root_radius_mm: float
    hole_diameter_mm: float
    hole_centres_mm: tuple
    n_flexures: int
    hardware: object
    material: MaterialSpec
    manufacturing: object


def describe(binding: str, value: float, limit: float, disk: str = "") -> str:
    """One sentence with the numbers of a failed check."""
    who = f"disk {disk}: " if disk else ""
    if binding == "energy_bound":
        return (f"{who}stores {value:.3g} J but flexures between the smallest contact radius "
                f"and the rim hold at most {limit:.3g} J at the design stress")
    if binding == "torque_cap":
        return (f"{who}peak torque {value / NMM_PER_NM:.3g} N*m > tip-ball torque cap "
                f"{limit / NMM_PER_NM:.3g} N*m at this r_c and thickness")
    if binding == "tip_ball_fit":
        if limit < 1:
            return (f"{who}no tip-ball radius keeps the Hertz contact at full deflection within "
                    f"the allowable stress for {value:.0f} or more flexures at this r_c")
        return (f"{who}tip balls sized for the load (bending and contact) fit {limit:.0f} "
                f"around r_c, fewer than the {value:.0f} flexures a disk needs")
    if binding == "flexure_fit":
        return f"{who}{value:.0f} flexures requested, at most {limit:.0f} tip balls fit around r_c"
    if binding == "rim_rule":
        return f"{who}{value:.0f} flexure roots do not fit inside R_o = {limit:.3g} mm (rim rule)"
    if binding == "straight_limit":
        return (f"{who}needs {value:.4g} rad, straight flexures reach only {limit:.4g} rad "
                "(search.flexure = \"straight\")")
    if binding == "serpentine_budget":
        return (f"{who}needs serpentine area ratio {value:.3f}, the tilt budget between "
                f"neighbours allows at most {limit:.3f}")
    if binding == "root_gap":
        return f"{who}gap between flexure roots {value:.3g} mm < {limit:.3g} mm the wire needs"
    if binding == "cam_tooth":
        return (f"{who}cam tooth tip {value:.3g} mm wide at this deflection and N < min_web_mm "
                f"{limit:.3g} mm (the disk turns too far per flexure pitch)")
    if binding == "cam_bore":
        return f"{who}cam web over the bore {value:.3g} mm < min_web_mm {limit:.3g} mm"
    if binding == HOLES:
        return (f"rim holes on the stack's common circle leave {value:.3g} mm to a rim edge "
                f"< min_hole_edge_mm {limit:.3g} mm (thin rim or rims of different depth)")
    if binding == DOWELS:
        return (f"a {value:.3g} mm rim is too thin for the rim dowels: no catalogue pin length "
                f"fits two rims and engages each by {limit:.3g} mm")
    if binding == STIFFNESS:
        return (f"the built flexures give {100 * value:+.2f} % stiffness, beyond the "
                f"+-{100 * limit:.3g} % tolerance (the tip web does not scale with the widths)")
    if binding == AXIAL:
        return f"stack height {value:.2f} mm > max_axial_length_mm {limit:.2f} mm"
    if binding == RADIAL:
        return f"envelope radius {value:.2f} mm > max_outer_radius_mm {limit:.2f} mm"
    if binding == "serpentine_shape":
        return (f"{who}no serpentine shape reaching the area ratio keeps the wire's concave edge "
                f"radius: {value:.3f} mm at best < {limit:.3g} mm")
    if binding == "root_fillet":
        return (f"{who}no root flare gives a buildable root: the fillet (r = {value:.3g} mm) "
                f"cannot be placed on the {limit:.3g} mm rim, or the fillets of neighbouring "
                "flexures overlap, or the flared flexures come too close")
    if binding == "web_stiffness":
        return (f"{who}the wire-EDM minimum webs near the flexure tips hold the beam stiffness "
                f"{value:.3f} x beyond what the FEA stiffness correction can bring onto the "
                "target (fewer or longer flexures, a thinner disk or a higher stiffness)")
    if binding in ("yield_margin", "fatigue_margin"):
        what = "yield" if binding == "yield_margin" else "fatigue (S_e)"
        return (f"{who}predicted peak {value:.0f} MPa > {limit:.0f} MPa that the required "
                f"{what} margin allows, at every beam stress the design tries")
    return binding


def _screen_groups(space, cols):
    """Screen disks A (every row) and B (mixed rows), each distinct disk once."""
    n_a, n_b, split = cols["n_a"], cols["n_b"], cols["split"]
    K, th = cols["target_stiffness_Nmm_per_rad"], cols["deflection_rad"]
    mixed = n_b > 0
    rows = np.flatnonzero(mixed)
    # stacks with a rim-to-rim joint: their disks' rims keep the rim spacer's room
    pinned = np.array([RIM in connection_sequence(int(k), space.inputs[j])[0]
                       and space.hardware.fastener_count > 0
                       for k, j in zip(n_a + n_b, cols["input"])], dtype=float)
    spec = np.concatenate([
        np.column_stack([n_a * K / split, split * th / n_a, cols["outer_radius_mm"], cols["z_a"],
                         cols["rc"], cols["material"], cols["n_flexures"], pinned]),
        np.column_stack([n_b[rows] * K[rows] / (1 - split[rows]),
                         (1 - split[rows]) * th[rows] / n_b[rows], cols["outer_radius_mm"][rows],
                         cols["z_b"][rows], cols["rc"][rows], cols["material"][rows],
                         cols["n_flexures"][rows], pinned[rows]])])
    uniq, inverse = np.unique(spec, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    mat = uniq[:, 5].astype(int)
    sigma = np.array(space.design_stress_MPa)[mat]
    E = np.array([m.youngs_modulus_MPa for m in space.materials])[mat]
    rho = np.array([m.density_kg_per_mm3 for m in space.materials])[mat]
    allowed, fatigue_limited, _ = space.stress_limits()
    res = screen_disks(uniq[:, 0], uniq[:, 1], uniq[:, 2], uniq[:, 3], uniq[:, 4], sigma, E, rho,
                       uniq[:, 6].astype(np.int64), min_tip_radius_mm=space.min_tip_radius_mm,
                       tip_radius_mm=space.tip_radius_mm,
                       manufacturing=space.manufacturing, hardware=space.hardware,
                       straight_only=space.flexure == "straight", allowed_peak_MPa=allowed[mat],
                       fatigue_limited=fatigue_limited[mat], contact=space.contact_limits(mat),
                       rim_pinned=uniq[:, 7] > 0.5)
    m = len(n_a)
    a = {k: v[inverse[:m]] for k, v in res.items()}
    b = {k: np.full(m, np.nan if v.dtype.kind == "f" else 0, dtype=v.dtype)
         for k, v in res.items()}
    for k, v in res.items():
        b[k][rows] = v[inverse[m:]]
    return a, b


def _stack_mass_kg(space, cols, a, b, i) -> float:
    """Stack mass of row ``i`` from the hardware layout rules (kg)."""
    mat = space.materials[cols["material"][i]]
    mspec = MaterialSpec(mat, space.design_stress_MPa[cols["material"][i]], space.yield_margin)

    def disk(name, g, z):
        rr, ro = float(g["rr"][i]), float(cols["outer_radius_mm"][i])
        return _Disk(name, float(z), ro, rr, float(g["ring_area_mm2"][i]),
                     float(g["cam_area_mm2"][i]), float(g["cam_tip_radius_mm"][i]),
                     float(g["cam_root_radius_mm"][i]), float(g["hole_diameter_mm"][i]),
                     ((0.5 * (rr + ro), 0.0),), int(g["n"][i]), space.hardware, mspec,
                     space.manufacturing)

    springs = ([disk("A", a, cols["z_a"][i])] * int(cols["n_a"][i])
               + [disk("B", b, cols["z_b"][i])] * int(cols["n_b"][i]))
    inp = space.inputs[cols["input"][i]]
    joints, out = connection_sequence(len(springs), inp)
    return sum(c.mass_kg for c in stack_layout(springs, joints, inp, out).components if c.in_mass)


def evaluate_batch(space, start: int, stop: int) -> dict[str, np.ndarray]:
    """Candidates ``start <= id < stop`` of ``space`` as columns (one row per stack).

    Columns carry units in their names; ``feasible``, ``binding`` (the first
    failed constraint or ""), ``binding_value`` and ``binding_limit`` (its
    numbers), ``binding_disk`` (A or B in a mixed stack) and ``violation``
    (fraction past the limit) say why a stack fails; :func:`detail` turns
    them into a sentence (only for the rows a report shows).
    """
    cols = space.decode(start, stop)
    if not cols:
        return {}
    m = len(cols["cid"])
    a, b = _screen_groups(space, cols)
    n_a, n_b = cols["n_a"], cols["n_b"]
    n = n_a + n_b
    mixed = n_b > 0
    hw, mfg = space.hardware, space.manufacturing
    ro = cols["outer_radius_mm"]
    height = n_a * cols["z_a"] + n_b * cols["z_b"] + (n - 1) * hw.rim_spacer_thickness_mm
    r_env = ro + np.where(n >= 3, BUSHING_CLEARANCE_MM + hw.bushing_wall_mm, 0.0)
    yield_mpa = np.array([mt.yield_strength_MPa for mt in space.materials])[cols["material"]]
    endurance = space.stress_limits()[2][cols["material"]]
    # the stack's peak: the more stressed disk (predicted peak of the real geometry)
    b_governs = mixed & (b["peak_stress_MPa"] > a["peak_stress_MPa"])
    peak_stress = np.where(b_governs, b["peak_stress_MPa"], a["peak_stress_MPa"])
    region = np.array(_REGIONS, dtype=object)[np.where(b_governs, b["peak_region"],
                                                       a["peak_region"])]
    margin = yield_mpa / peak_stress
    fatigue_margin = endurance / peak_stress

    binding = np.array([""] * m, dtype=object)
    value, limit = np.full(m, np.nan), np.full(m, np.nan)
    which = np.array([""] * m, dtype=object)
    for g, label, mask in ((a, "A", np.ones(m, dtype=bool)), (b, "B", mixed)):
        bad = mask & (g["code"] > 0) & (binding == "")
        for code, reason in REASONS.items():
            sel = bad & (g["code"] == code)
            binding[sel] = reason
            value[sel], limit[sel] = g["value"][sel], g["limit"][sel]
            which[sel] = np.where(mixed[sel], label, "")
    # rim holes on one circle through every rim (design.job.common_hole_circle's rule)
    r_hole = 0.5 * a["hole_diameter_mm"]
    rr_max = np.where(mixed, np.fmax(a["rr"], b["rr"]), a["rr"])
    circle = 0.5 * (rr_max + ro)
    hole_edge = np.where(a["n_holes"] > 0, np.fmin(circle - r_hole - rr_max, ro - circle - r_hole),
                         np.inf)
    edge_mm = mfg.min_hole_edge_mm
    # beam stiffness of the built widths, in series (design.stack), against the target
    k_built = 1.0 / (n_a / a["stiffness_Nmm_per_rad"]
                     + np.where(mixed, n_b / b["stiffness_Nmm_per_rad"], 0.0))
    k_error = k_built / cols["target_stiffness_Nmm_per_rad"] - 1.0
    for name, val, lim, bad in (
            (STIFFNESS, k_error, space.stiffness_tolerance,
             np.abs(k_error) > space.stiffness_tolerance),
            (HOLES, hole_edge, edge_mm, hole_edge < edge_mm - 1e-9),
            (AXIAL, height, space.max_axial_length_mm, height > space.max_axial_length_mm + 1e-9),
            (RADIAL, r_env, space.max_outer_radius_mm, r_env > space.max_outer_radius_mm + 1e-9)):
        sel = bad & (binding == "")
        binding[sel] = name
        value[sel] = np.broadcast_to(val, (m,))[sel]
        limit[sel] = np.broadcast_to(lim, (m,))[sel]
    # mass where every disk is designable (infeasible on envelope/yield still get one: the
    # report quotes the lightest near miss); a stack whose rim joints cannot be laid out
    # (no catalogue dowel fits its rims) fails on that
    disk_ok = (a["code"] == 0) & (~mixed | (b["code"] == 0))
    mass = np.full(m, np.nan)
    for i in np.flatnonzero(disk_ok):
        try:
            mass[i] = _stack_mass_kg(space, cols, a, b, i)
        except DesignError:
            if binding[i] == "":
                binding[i] = DOWELS
                value[i] = min(cols["z_a"][i], cols["z_b"][i] if mixed[i] else np.inf)
                limit[i] = MIN_ENGAGEMENT_PER_DIAMETER * hw.fastener_diameter_mm
    feasible = binding == ""
    with np.errstate(divide="ignore", invalid="ignore"):
        smaller_bad = np.isin(binding, list(_SMALLER_BAD))
        violation = np.where(smaller_bad, limit / value - 1.0, value / limit - 1.0)
        violation = np.where(binding == STIFFNESS, np.abs(value) / limit - 1.0, violation)
    violation[binding == "rim_rule"] = np.nan
    violation[feasible] = 0.0

    K, th = cols["target_stiffness_Nmm_per_rad"], cols["deflection_rad"]
    energy = 0.5 * K * th ** 2 * J_PER_NMM
    volume_cm3 = np.pi * r_env ** 2 * height / MM3_PER_CM3
    w_gap = mfg.w_gap_mm
    d_max = gap_range_mm(w_gap, mfg.t_spring_mm, mfg.t_shaft_mm)[2]
    n_cams = np.array([len(set(camshaft_indices(connection_sequence(int(k), space.inputs[j])[0])))
                       for k, j in zip(n, cols["input"])])
    cut = (n_a * a["cut_ring_mm"] + np.where(mixed, n_b * b["cut_ring_mm"], 0.0)
           + n_cams * a["cut_cam_mm"])
    fams = space.families
    return {
        "cid": cols["cid"],
        "family": np.array([fams[f].label for f in cols["family"]], dtype=object),
        "n_disks": n, "n_a": n_a, "n_b": n_b,
        "material": np.array([space.materials[j].name for j in cols["material"]], dtype=object),
        "input": np.array([space.inputs[j] for j in cols["input"]], dtype=object),
        "target_stiffness_Nm_per_rad": K / NMM_PER_NM, "stiffness_built_error": k_error,
        "deflection_rad": th, "peak_torque_Nm": K * th / NMM_PER_NM,
        "outer_radius_mm": ro, "thickness_a_mm": cols["z_a"], "thickness_b_mm": cols["z_b"],
        "contact_radius_mm": cols["rc"], "split": cols["split"],
        "n_flexures_a": a["n"], "n_flexures_b": b["n"],
        "root_radius_a_mm": a["rr"], "root_radius_b_mm": b["rr"],
        "tip_radius_a_mm": a["rb"], "straight_a": a["straight"].astype(bool),
        "serpentine_factor_a": a["s"], "serpentine_factor_b": b["s"],
        "beam_stress_a_MPa": a["beam_stress_MPa"], "beam_stress_b_MPa": b["beam_stress_MPa"],
        "stress_derating_a": a["derating"], "stress_derating_b": b["derating"],
        "root_flare_a": a["root_flare"], "root_flare_b": b["root_flare"],
        "peak_stress_MPa": peak_stress, "peak_region": region, "yield_margin": margin,
        "fatigue_margin": fatigue_margin,
        "derated_binding": np.array([REASONS.get(int(c), "") for c in np.where(
            mixed & (a["code"] == 0), b["derated_code"], a["derated_code"])], dtype=object),
        "mass_kg": mass, "axial_length_mm": height, "envelope_radius_mm": r_env,
        "backlash_nominal_rad": n * backlash_rad(2 * w_gap, cols["rc"]),
        "backlash_worst_rad": n * backlash_rad(d_max, cols["rc"]),
        "energy_J": energy, "energy_density_J_per_cm3": energy / volume_cm3,
        "specific_energy_J_per_kg": energy / mass, "edm_cut_length_mm": cut,
        "feasible": feasible, "binding": binding, "binding_value": value,
        "binding_limit": limit, "binding_disk": which, "violation": violation,
    }


def detail(cols: dict, i: int) -> str:
    """The sentence with the numbers of row ``i``'s binding constraint ("" if feasible)."""
    b = cols["binding"][i]
    return describe(b, cols["binding_value"][i], cols["binding_limit"][i],
                    cols["binding_disk"][i]) if b else ""
