"""Finalists: the full design of the best screened stacks, FEA of the top ones, the winner's job.

A candidate row becomes a job document (the same dict is validated by
:func:`springcad.config.job_from_dict`, designed by
:func:`springcad.design.job.design_job` and written as the winner's TOML), so
what was designed and verified is exactly what ``springcad build`` will read.
The screened N is written into the job (``n_flexures``) so the full design keeps
the screened layout; the tip ball is sized by the design for the peak load. The job's
``safety_factor`` is the yield margin the requirements need (the fatigue margin
included, :meth:`Requirements.required_yield_margin`), so the design's stress passes
lower the beam stress exactly as the screening did. The full design runs with
``explain=False`` (a spring that cannot keep the margin fails at once, without the
search for the thickness or deflection that would fit).
Units: N*m/rad and degrees only in the job document (the config's units).
"""

from __future__ import annotations

import math

import numpy as np

from fea.study import verify_options
from fea.verify import verify_job
from springcad.config import job_from_dict
from springcad.design.flexure import concave_edge_radius_mm
from springcad.design.job import design_job
from springcad.errors import SpringcadError
from springcad.geometry.checks import build_and_check
from springcad.options import VERIFY
from springcad.progress import no_progress
from springcad.units import MM3_PER_CM3, NMM_PER_NM


def job_document(req, cand: dict) -> dict:
    """The job config (as a TOML-ready dict) of a candidate row of the sweep."""
    n_a, n_b, split = int(cand["n_a"]), int(cand["n_b"]), float(cand["split"])
    K, th = cand["target_stiffness_Nm_per_rad"], cand["deflection_rad"]
    mat = next(m for m in req.materials if m.name == cand["material"])
    ball = ({"tip_radius_mm": req.search.tip_radius_mm} if req.search.tip_radius_mm is not None
            else {"min_tip_radius_mm": req.search.min_tip_radius_mm})

    def spring(k_nm, theta, z, n):
        return {"target_stiffness_Nm_per_rad": round(float(k_nm), 9),
                "max_deflection_rad": round(float(theta), 12),
                "outer_radius_mm": round(float(cand["outer_radius_mm"]), 9),
                "thickness_mm": float(z), "contact_radius_mm": float(cand["contact_radius_mm"]),
                "n_flexures": int(n), **ball,
                "flexure": "straight" if req.search.flexure == "straight" else "auto"}

    springs = {"A": spring(n_a * K / split, split * th / n_a, cand["thickness_a_mm"],
                           cand["n_flexures_a"])}
    sequence = ["A"] * n_a
    if n_b:
        springs["B"] = spring(n_b * K / (1 - split), (1 - split) * th / n_b,
                              cand["thickness_b_mm"], cand["n_flexures_b"])
        sequence += ["B"] * n_b
    fam = cand["family"]
    return {
        "job": {"name": f"{req.name}_winner" if req.name else "synthesized",
                "description": (f"synthesized by springcad: {fam}, candidate {int(cand['cid'])}, "
                                f"{req.target_stiffness_Nmm_per_rad / NMM_PER_NM:g} N*m/rad over "
                                f"+-{math.degrees(req.deflection_rad):.4g} deg")},
        "material": {"name": mat.name, "design_stress_MPa": round(req.design_stress_MPa(mat), 6),
                     "safety_factor": round(req.required_yield_margin(mat), 9)},
        "springs": springs,
        "stack": {"sequence": sequence, "input": cand["input"]},
        "manufacturing": dict(req.manufacturing_table),
        "hardware": dict(req.hardware_table),
        **({"duty": dict(req.duty_table)} if req.duty_table else {}),
    }


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):  # an inline table, e.g. a [[duty.blocks]] entry
        return "{" + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"no TOML form for {v!r}")


def toml_text(doc: dict, header: str = "") -> str:
    """A job document (tables of scalars, lists and inline tables; ``springs`` nested) as
    TOML text."""
    lines = [f"# {h}" if h else "#" for h in header.splitlines()] if header else []
    for section, table in doc.items():
        if section == "springs":
            for name, spec in table.items():
                lines += ["", f"[springs.{name}]"] + [f"{k} = {_toml_value(v)}" for k, v in spec.items()]
            continue
        lines += ["", f"[{section}]"] + [f"{k} = {_toml_value(v)}" for k, v in table.items()]
    return "\n".join(lines).lstrip("\n") + "\n"


def design_candidate(req, cand: dict):
    """Full design (:class:`~springcad.design.job.JobDesign`) of a candidate row.

    :func:`springcad.design.job.design_job` itself (the rim and spacer room of a stack,
    shared camshafts, hardware checks), with ``explain=False``: a yes or no is all the
    synthesis needs.

    Raises:
        DesignError: the exact design fails a check the screening does not make.
    """
    job = job_from_dict(job_document(req, cand), name="synthesized")
    return design_job(job, explain=False)


#: failure classes of a finalist, by a phrase of the design's message (first match wins)
FAILURE_CLASSES = (("yield margin", "yield_margin"), ("fatigue margin", "fatigue_margin"),
                   ("duty not met", "duty"),
                   ("fillet", "fillet"), ("neighbour", "neighbour_clearance"),
                   ("edge radius", "concave_edge_radius"), ("rim holes", "rim_holes"), ("cam", "cam"),
                   ("stack height", "axial_length"), ("envelope radius", "envelope_radius"),
                   ("stiffness", "stiffness"), ("deflection", "deflection"))


def failure_class(message: str) -> str:
    """A short name for why a finalist failed (:data:`FAILURE_CLASSES`, else "other")."""
    low = message.lower()
    return next((name for phrase, name in FAILURE_CLASSES if phrase in low), "other")


def full_design_summary(req, cand: dict) -> dict:
    """Dask task: the full design of one candidate, checked against the requirements.

    Returns a dict with ``ok``, ``error`` (what failed, "" if nothing), ``failure``
    (:func:`failure_class`) and the exact numbers next to the screened ones (mass,
    height, envelope radius, stiffness, each spring's N, R_r, flexure kind, predicted
    peak stress, yield and fatigue margins, beam-stress derating, root flare).
    """
    out = {"cid": int(cand["cid"]), "screened_mass_kg": float(cand["mass_kg"]),
           "screened_peak_stress_MPa": float(cand["peak_stress_MPa"])}
    try:
        jd = design_candidate(req, cand)
    except SpringcadError as err:
        return {**out, "ok": False, "error": str(err), "failure": failure_class(str(err))}
    st = jd.stack
    fails = []
    for name, s in jd.springs.items():
        need = req.required_yield_margin(s.material.material)
        if s.yield_margin < need * (1 - 1e-3):
            fails.append(f"spring {name}: predicted peak {s.predicted_peak_stress_MPa:.0f} MPa at the "
                         f"{s.stress.region} leaves a yield margin {s.yield_margin:.3f} < {need:.3f}")
        fat = s.fatigue
        if req.fatigue_margin is not None and (fat is None or fat.margin < req.fatigue_margin * (1 - 1e-3)):
            fails.append(f"spring {name}: fatigue margin "
                         f"{'n/a' if fat is None else f'{fat.margin:.3f}'} < {req.fatigue_margin:g}")
        check = s.duty_check
        if req.duty is not None and (check is None or not check.met):
            fails.append(f"spring {name}: duty not met (fatigue safety factor "
                         f"{'n/a' if check is None else f'{check.safety_factor:.3f}'} < "
                         f"{req.duty.safety_factor:g})")
    if st.height_mm > req.max_axial_length_mm + 1e-9:
        fails.append(f"stack height {st.height_mm:.2f} mm > {req.max_axial_length_mm:g} mm")
    if st.envelope_radius_mm > req.max_outer_radius_mm + 1e-9:
        fails.append(f"envelope radius {st.envelope_radius_mm:.2f} mm > "
                     f"{req.max_outer_radius_mm:g} mm")
    k_err = st.stiffness_Nmm_per_rad / req.target_stiffness_Nmm_per_rad - 1
    if abs(k_err) > req.stiffness_tolerance:
        fails.append(f"beam stiffness {100 * k_err:+.2f} % off target")
    if st.max_deflection_rad < req.deflection_rad * (1 - 1e-6):
        fails.append(f"deflection {st.max_deflection_rad:.4f} rad < {req.deflection_rad:.4f} rad")
    error = "; ".join(fails)
    return {**out, "ok": not fails, "error": error, "failure": failure_class(error) if fails else "",
            "mass_kg": st.mass_kg, "axial_length_mm": st.height_mm,
            "envelope_radius_mm": st.envelope_radius_mm,
            "stiffness_Nm_per_rad": st.stiffness_Nmm_per_rad / NMM_PER_NM,
            "max_deflection_rad": st.max_deflection_rad,
            "backlash_nominal_rad": st.backlash.nominal,
            "energy_density_J_per_cm3": st.energy_J / (st.envelope_volume_mm3 / MM3_PER_CM3),
            "specific_energy_J_per_kg": st.energy_J / st.mass_kg,
            "peak_stress_MPa": max(s.predicted_peak_stress_MPa for s in jd.springs.values()),
            "yield_margin": min(s.yield_margin for s in jd.springs.values()),
            "fatigue_margin": min((s.fatigue.margin for s in jd.springs.values()
                                   if s.fatigue is not None), default=None),
            "springs": {n: {"n_flexures": s.n_flexures, "root_radius_mm": s.root_radius_mm,
                            "min_concave_edge_radius_mm": _edge_radius_mm(s),
                            "tip_radius_mm": s.tip_radius_mm, "flexure": s.flexure,
                            "mass_kg": s.mass_kg, "beam_stress_MPa": s.beam_stress_MPa,
                            "stress_derating": s.stress_derating, "root_flare": s.root_flare,
                            "peak_stress_MPa": s.predicted_peak_stress_MPa,
                            "peak_region": s.stress.region if s.stress is not None else None,
                            "yield_margin": s.yield_margin,
                            "fatigue_margin": s.fatigue.margin if s.fatigue is not None else None,
                            "warnings": list(s.warnings)}
                        for n, s in jd.springs.items()},
            "notes": jd.notes()}


def _edge_radius_mm(design) -> float | None:
    """Smallest concave flexure-edge radius (mm; None for straight flexures): the FEA finds
    the peak stress of tight serpentine turns there, far above the beam stress."""
    if design.centreline.is_straight:
        return None
    y = np.linspace(design.contact_radius_mm, design.root_station_mm, 1201)
    return concave_edge_radius_mm(design.centreline, y, design.width_mm(y))


def verify_candidate(req, cand: dict, model: str = "2d3d", levels: int = 3, progress=None):
    """FEA verification (and width correction) of a candidate's springs.

    The options are ``springcad build``'s (:class:`fea.study.VerifyOptions` defaults:
    2D convergence study with the 3D factor, stiffness correction, stress passes, cam
    contact sweep) but for ``model`` and the stiffness tolerance, which is the
    requirement's when that is tighter than the build's.

    Returns:
        ``(verification, corrected)``: the :class:`fea.verdict.JobVerification` (``.ok``,
        ``.failures()``; :func:`springcad.report.tables.verification_table` prints it) and
        the job design with the FEA-corrected springs (what ``springcad build`` makes its
        solids from).
    """
    jd = design_candidate(req, cand)
    opts = verify_options(model=model, levels=levels, keep_fields=False,
                          tolerance_pct=min(VERIFY.tolerance_pct, 100.0 * req.stiffness_tolerance))
    v = verify_job(jd, opts, progress or no_progress)
    return v, v.corrected_job_design(jd)


def build_checks(job_design, progress=None) -> dict:
    """``springcad build``'s solids and checks (:func:`~springcad.geometry.checks.build_and_check`,
    as ``sc.build`` runs them) on a job design, without writing files.

    Returns:
        ``{"ok", "summary", "failures"}``: ``ok`` as build decides it (no geometry error and
        no manufacturability violation); one line per failed check.

    Raises:
        GeometryError, StageError: a part cannot be made (as ``build`` would stop).
    """
    _, report, _ = build_and_check(job_design, progress)
    return {"ok": report.passed(), "summary": report.summary(),
            "failures": [f"{c.subject}: {c.name}: {c.message}"
                         for c in report.errors + report.violations]}
