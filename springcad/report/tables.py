"""Plain-text tables of a designed and of a verified job, for the terminal.

The results (:class:`springcad.design.job.JobDesign`, :class:`fea.verdict.JobVerification`)
hold data; the text a person reads is made here, as :mod:`springcad.report.notebook` makes
their notebook views. ``springcad design``, ``verify`` and ``build`` print these tables, the
API's results give them as ``summary()``, and the synthesis keeps one per verified finalist.
Units as printed: stiffness N*m/rad, angles deg or rad (named), stresses MPa, clearances um.
"""

from __future__ import annotations

from springcad.design import duty
from springcad.units import G_PER_KG, MM3_PER_CM3, NMM_PER_NM, UM_PER_MM, rad_to_deg

__all__ = ["contact_line", "design_table", "verification_table"]


def _aligned(rows: list[tuple[str, ...]]) -> list[str]:
    """Rows of cells, right-aligned in columns two spaces apart."""
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in rows]


def design_table(job_design) -> str:
    """A designed job as a short plain-text table: one row per spring, the stack (stiffness,
    eq. 10 limit, backlash, energy, mass), the duty rating of every spring and the notes.

    Args:
        job_design: a :class:`springcad.design.job.JobDesign` (N*mm, mm, rad inside).
    """
    rows = [("spring", "K N*m/rad", "target", "theta_max deg", "N", "r_c mm", "R_r mm",
             "tip mm", "flexure", "J/cm3", "J/kg")]
    for s in job_design.springs.values():
        rows.append((s.name, f"{s.stiffness_beam_Nmm_per_rad / NMM_PER_NM:.2f}",
                     f"{s.target_stiffness_Nmm_per_rad / NMM_PER_NM:.2f}",
                     f"{rad_to_deg(s.max_deflection_rad):.2f}", str(s.n_flexures),
                     f"{s.contact_radius_mm:.3f}", f"{s.root_radius_mm:.3f}",
                     f"{s.tip_radius_mm:.3f}", s.flexure,
                     f"{s.energy_density_J_per_cm3:.3f}", f"{s.specific_energy_J_per_kg:.1f}"))
    lines = _aligned(rows)
    st = job_design.stack
    b = st.backlash
    lines += [
        "",
        f"stack {' + '.join(st.sequence)}: input {st.input}, output {st.output}, joints "
        f"{', '.join(j + '-to-' + j for j in st.joints) or 'none'}",
        f"  K = {st.stiffness_Nmm_per_rad / NMM_PER_NM:.2f} N*m/rad "
        f"(target {st.target_stiffness_Nmm_per_rad / NMM_PER_NM:.2f}), max deflection "
        f"{st.max_deflection_rad:.3f} rad ({rad_to_deg(st.max_deflection_rad):.1f} deg, eq. 10)",
        f"  backlash rad: nominal {b.nominal:.4f}, worst [{b.worst_min:.4f}, {b.worst_max:.4f}], "
        f"RSS [{b.rss_min:.4f}, {b.rss_max:.4f}], MC p1-p99 [{b.mc_p01:.4f}, {b.mc_p99:.4f}]",
        f"  energy {st.energy_J:.2f} J, mass {st.mass_kg * G_PER_KG:.1f} g, "
        f"{st.energy_J / (st.envelope_volume_mm3 / MM3_PER_CM3):.3f} J/cm3, "
        f"{st.energy_J / st.mass_kg:.1f} J/kg",
    ]
    lines.append(f"duty: {duty.describe(job_design.job.material.duty)}")
    for s in job_design.springs.values():
        check = s.duty_check
        lines.append(
            f"{s.name}: beam stress {s.peak_stress_MPa:.0f} MPa, predicted peak "
            f"{s.predicted_peak_stress_MPa:.0f} MPa at the {s.stress.region if s.stress else '-'}, "
            f"yield margin {s.yield_margin:.3f} (required {s.material.safety_factor:g}; "
            f"{s.required_yield_margin:.3g} with the duty), root flare {s.root_flare:g}")
        lines.append(f"  {s.name} " + ("duty not checked: no fatigue data for "
                                       f"{s.material.material.name}" if check is None
                                       else check.rating_text()))
        if s.duty_advice:
            lines.append(f"  {s.name}: sized for yield alone: {s.duty_advice}")
    lines += [f"note: {n}" for n in job_design.notes()]
    return "\n".join(lines)


def contact_line(spring_verification) -> str | None:
    """One line of a verified spring's contact at +-theta_max: the ball's contact von Mises
    and the smallest worst-case clearance (um); None without a contact sweep.

    Args:
        spring_verification: a :class:`fea.verdict.SpringVerification`.
    """
    v = spring_verification
    at_max = getattr(v.contact, "at_max", None)
    if at_max is None:
        return None
    ends = [e for e in at_max.ends.values() if e.clearances]
    worst = min((c for e in ends for c in e.clearances), key=lambda c: c.worst_case_mm,
                default=None)
    vm = at_max.contact_von_mises_MPa
    text = (f"contact {v.name} at +-theta_max: tip ball von Mises {vm:.0f} MPa (yield "
            f"margin {v.yield_strength_MPa / vm:.3f}, required "
            f"{v.required_safety_factor:.3g})")
    if worst is not None:
        text += (f"; smallest worst-case clearance {UM_PER_MM * worst.worst_case_mm:.1f} um "
                 f"({worst.name.replace('/', ' to ').replace('_', ' ')}, nominal "
                 f"{UM_PER_MM * worst.nominal_mm:.1f} um, tolerances t_spring + t_shaft "
                 f"{UM_PER_MM * (at_max.t_spring_mm + at_max.t_shaft_mm):.0f} um)")
    return text


def verification_table(job_verification) -> str:
    """A verified job as a short plain-text table: one row per spring (FEA and beam
    stiffness, errors, peak stress, margins, duty), the stack, then ratings, failures,
    notes and the contact findings.

    Args:
        job_verification: a :class:`fea.verdict.JobVerification` (N*mm inside).
    """
    jv = job_verification
    rows = [("spring", "K_fea", "K_beam", "target", "err %", "disc %", "sigma MPa", "design",
             "where", "margin", "req", "duty", "iters", "ok alone")]
    for n, v in jv.springs.items():
        r = v.run.peak_result
        dc = v.duty_check
        fat_txt = "-" if dc is None else f"D {dc.miner_sum:.2g} n {dc.safety_factor:.2f}"
        rows.append((n, f"{v.stiffness_fea_Nmm_per_rad / NMM_PER_NM:.2f}",
                     f"{v.design.stiffness_beam_Nmm_per_rad / NMM_PER_NM:.2f}",
                     f"{v.target_stiffness_Nmm_per_rad / NMM_PER_NM:.2f}",
                     f"{100 * v.error_vs_target:+.2f}", f"{100 * v.run.stiffness_error:.3f}",
                     f"{v.peak_von_mises_MPa:.0f}", f"{v.design.predicted_peak_stress_MPa:.0f}",
                     r.peak_region, f"{v.yield_margin:.3f}", f"{v.required_safety_factor:.2f}",
                     fat_txt, str(len(v.iterations) - 1), "yes" if v.ok else "NO"))
    lines = _aligned(rows)
    st = jv.stack
    lines.append(f"stack {' + '.join(st.sequence)}: K_fea "
                 f"{st.stiffness_Nmm_per_rad / NMM_PER_NM:.2f} N*m/rad (target "
                 f"{st.target_Nmm_per_rad / NMM_PER_NM:.2f}), limit "
                 f"{st.max_deflection_rad:.3f} rad at "
                 f"{st.torque_at_limit_Nmm / NMM_PER_NM:.2f} N*m")
    lines.append("sigma: FEA peak von Mises at the max deflection; design: the design's "
                 "prediction for the same geometry; duty: Miner sum D and fatigue safety "
                 "factor n of the duty at the critical point of the FEA field")
    lines += [f"duty: {r}" for r in jv.ratings()]
    lines += [f"contact fatigue: {r}" for r in jv.contact_fatigue_notes()]
    lines += [f"FAIL: {f}" for f in jv.failures()]
    lines += [f"note: {n}" for n in jv.notes()]
    lines += [f"contact {n}: {f['message']}" for n, v in jv.springs.items()
              if v.contact is not None for f in v.contact.flags]
    lines += [t for t in (contact_line(v) for v in jv.springs.values()) if t]
    stops = jv.release_failures()
    if stops:
        lines.append(f"contact at full deflection: {len(stops)} finding"
                     f"{'s' if len(stops) != 1 else ''} stop a release (the release gate "
                     "lists them; fea.json release_failures)")
    return "\n".join(lines)
