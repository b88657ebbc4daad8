"""The verdicts of a verification: a verified spring, a stack, a whole job.

:class:`SpringVerification` (FEA stiffness and stress with their errors, the
correction history, pass or fail with the reasons), :class:`StackVerification`
(series K and the eq. 10 load case from the FEA stiffnesses, made by
:func:`verify_stack`) and :class:`JobVerification` (every spring and the stack;
``to_dict`` is the ``fea.json`` document, ``summary`` the printed table).
:class:`VerificationFailed` is raised for a failed verdict. The studies behind
them are :mod:`fea.study`, the correction loop :mod:`fea.verify`.
Units: mm, N, MPa, N*mm, rad; JSON keys carry N*m where they say so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from fea.fatigue import region_peaks_MPa
from fea.problem import LoadCase
from fea.study import ModelRun, VerifyOptions
from springcad.design import contact_fatigue, duty, fatigue
from springcad.design.stack import eq10_limit, series_stiffness
from springcad.errors import CheckFailed, one_line
from springcad.units import NMM_PER_NM
from springcad.version import stamp

SCHEMA = "springcad.fea/1"


class VerificationFailed(CheckFailed):
    """A verified spring or stack misses its stiffness target or its stress limit."""


# ================================================================== one spring
#: what a duty failure of a job without a [duty] adds: the duty is springcad's default and
#: how to declare the one the spring will see (said once per job, after its last failure)
DEFAULT_DUTY_HINT = ("; the job declares no [duty], so springcad's default is the duty: "
                     "declare the one the spring will see ([duty] blocks of cycles, a time "
                     "series or a preset, e.g. preset = \"static\" for a prototype: 1e3 "
                     "reversals at +-theta_max; README: Duty)")
#: the starts of the verification notes that say what a contact correction tried and why
#: it was not kept (fea.verify): the release reasons carry them beside the contact failures
CORRECTIONS_TRIED = ("cam redesign", "contact correction stopped", "cam clearance correction")


@dataclass(repr=False)
class SpringVerification:
    """The verified spring: FEA stiffness and stress with errors, and the correction history.

    Stiffness N*mm/rad, stress MPa, lengths mm; ``to_dict`` gives the ``fea.json`` entry.
    """

    name: str
    design: object
    """The final (corrected) :class:`~springcad.design.spring.SpringDesign`."""
    original: object
    run: ModelRun
    model: str
    tolerance: float
    iterations: list
    required_safety_factor: float
    yield_strength_MPa: float
    timings_s: dict
    case: LoadCase
    notes: list = field(default_factory=list)
    support: dict | None = None
    contact: object | None = None
    """The :class:`~fea.contact_result.ContactSweep` of the final design (None: not run)."""

    def __repr__(self) -> str:
        return (f"SpringVerification({self.name!r}, K_fea={self.stiffness_fea_Nmm_per_rad:.6g} "
                f"N*mm/rad ({100 * self.error_vs_target:+.2f} % vs target), peak "
                f"{self.peak_von_mises_MPa:.0f} MPa, ok={self.ok})")

    @property
    def stiffness_fea_Nmm_per_rad(self) -> float:
        return self.run.stiffness_Nmm_per_rad

    @property
    def target_stiffness_Nmm_per_rad(self) -> float:
        return self.design.target_stiffness_Nmm_per_rad

    @property
    def error_vs_target(self) -> float:
        return self.stiffness_fea_Nmm_per_rad / self.target_stiffness_Nmm_per_rad - 1.0

    @property
    def peak_von_mises_MPa(self) -> float:
        return self.run.peak_stress_MPa

    @property
    def yield_margin(self) -> float:
        return self.yield_strength_MPa / self.peak_von_mises_MPa

    @property
    def fatigue(self):
        """Fully reversed fatigue at +-theta_max from the FEA peak, with the duty's surface and
        reliability (or None without data)."""
        d = self.design.material.duty
        return fatigue.check(self.design.material.material.name, self.peak_von_mises_MPa,
                             d.surface, d.reliability)

    def duty_points_MPa(self) -> dict[str, float]:
        """Von Mises at theta_max at the critical points of the verified field (MPa): per
        region of the cut faces, its 2D Richardson extrapolation times its own 3D factor
        (:func:`fea.fatigue.region_peaks_MPa`; the sector's artificial cut faces are left
        out). The verified peak (:attr:`peak_von_mises_MPa`, the yield check's) is the 2D
        peak times the 3D factor of the peaks, which mixes two regions when the 2D and 3D
        peaks sit in different ones."""
        return region_peaks_MPa(self.run)

    @property
    def duty_check(self):
        """The duty at the verified stress field's critical point (the lowest fatigue safety
        factor over :meth:`duty_points_MPa`), or None without fatigue data."""
        d = self.design
        checks = [duty.check(d.material.duty, d.material.material.name, peak,
                             d.max_deflection_rad, where=f"FEA {region}")
                  for region, peak in self.duty_points_MPa().items() if peak > 0]
        checks = [c for c in checks if c is not None]
        return min(checks, key=lambda c: c.safety_factor) if checks else None

    @property
    def contact_fatigue(self):
        """Contact fatigue of the tip ball over the duty
        (:func:`springcad.design.contact_fatigue.contact_check`) from the largest Hertz
        pressure of the contact sweep at +-theta_max (nominal geometry), or None (no
        sweep, no contact, no contact-fatigue data)."""
        at_max = getattr(self.contact, "at_max", None)
        if at_max is None:
            return None
        p0 = self._hardest_contact().get("p0_MPa", 0.0)
        d = self.design
        return contact_fatigue.contact_check(d.material.duty, d.material.material.name, p0,
                                             d.max_deflection_rad)

    def _hardest_contact(self) -> dict:
        """The contact entry (force, ball and flank radius, p0) of the sweep's end at
        +-theta_max with the largest Hertz pressure ({} without a sweep)."""
        at_max = getattr(self.contact, "at_max", None)
        ends = [e.contact for e in at_max.ends.values()] if at_max is not None else []
        return max(ends, key=lambda c: c.get("p0_MPa", 0.0), default={})

    def contact_fatigue_failures(self) -> list[str]:
        """Why the tip ball's contact fatigue over the duty stops a release (empty when it
        is met or not judged), with the changes that would meet it."""
        c = self.contact_fatigue
        if c is None or not c.judged or c.met:
            return []
        h, m = self._hardest_contact(), self.design.material.material
        d = self.design
        mfg = d.manufacturing
        change = c.changes(h["force_N"], h["ball_radius_mm"], d.thickness_mm,
                           m.youngs_modulus_MPa, m.poisson_ratio, d.contact_radius_mm,
                           mfg.w_gap_mm, d.max_deflection_rad,
                           mfg.t_spring_mm + mfg.t_shaft_mm)
        return [f"spring {self.name}: tip-ball contact fatigue over the duty not met: "
                f"{c.text()}; {change}"]

    def duty_failures(self) -> list[str]:
        """Why the duty stops a release (empty when it is met or static/prototype): the
        flexures' fatigue and the tip balls' contact fatigue; when the job declares no
        duty, the last says that springcad's default is the duty and how to declare one."""
        out = self._flexure_duty_failures() + self.contact_fatigue_failures()
        if out and not self.design.material.duty.declared:
            out[-1] += DEFAULT_DUTY_HINT
        return out

    def _flexure_duty_failures(self) -> list[str]:
        c = self.duty_check
        if c is None:
            return [f"spring {self.name}: duty not checked: no fatigue data for "
                    f"{self.design.material.material.name} (springcad/data/fatigue.csv)"]
        if c.met:
            return []
        life = duty.life_text(c.life_at_max_cycles)
        return [f"spring {self.name}: duty ({duty.describe(c.duty)}) not met at the {c.where} "
                f"({c.peak_MPa:.0f} MPa at theta_max): Miner sum {c.miner_sum:.3g}, fatigue "
                f"safety factor {c.safety_factor:.2f} < {c.required_safety_factor:g}; rated "
                f"life at +-{math.degrees(c.theta_max_rad):.1f} deg {life}, fatigue-rated "
                f"deflection {math.degrees(c.rated_deflection_rad):.1f} deg"
                + (f"; {self.design.duty_advice}" if self.design.duty_advice else "")]

    @property
    def stiffness_ok(self) -> bool:
        return abs(self.error_vs_target) <= self.tolerance

    @property
    def stress_ok(self) -> bool:
        return self.yield_margin >= self.required_safety_factor

    @property
    def ok(self) -> bool:
        return self.stiffness_ok and self.stress_ok

    def failures(self) -> list[str]:
        return self.stiffness_failures() + self.stress_failures()

    def stiffness_failures(self) -> list[str]:
        out = []
        if not self.stiffness_ok:
            out.append(f"spring {self.name}: FEA stiffness "
                       f"{self.stiffness_fea_Nmm_per_rad / NMM_PER_NM:.2f} N*m/rad misses the "
                       f"target {self.target_stiffness_Nmm_per_rad / NMM_PER_NM:.2f} by "
                       f"{100 * self.error_vs_target:+.2f} % "
                       f"(tolerance {100 * self.tolerance:.2g} %)"
                       + "".join(f"; {n}" for n in self.notes if "correction stopped" in n))
        return out

    def stress_failures(self) -> list[str]:
        out = []
        if not self.stress_ok:
            r = self.run.peak_result
            out.append(
                f"spring {self.name}: peak von Mises {self.peak_von_mises_MPa:.0f} MPa at the "
                f"{r.peak_region} gives a yield margin {self.yield_margin:.3f} below the required "
                f"{self.required_safety_factor:.3g} after the stress correction (see the "
                "correction iterations and notes): lower design_stress_MPa, thicken the disk "
                "or lower the deflection")
        return out

    def contact_failures(self) -> list[str]:
        """Why the contact at +-theta_max (ball stress, clearances with the profile
        tolerances) stops a release (:mod:`fea.contact_tolerance`); empty without a sweep."""
        at_max = getattr(self.contact, "at_max", None)
        return at_max.failures() if at_max is not None else []

    def to_dict(self) -> dict:
        run, d = self.run, self.design
        st = run.study
        pr = run.peak_result
        finest = st.finest
        q2 = finest.mesh
        out = {
            "stiffness_fea_Nm_per_rad": self.stiffness_fea_Nmm_per_rad / NMM_PER_NM,
            "stiffness_beam_Nm_per_rad": d.stiffness_beam_Nmm_per_rad / NMM_PER_NM,
            "stiffness_beam_original_Nm_per_rad":
                self.original.stiffness_beam_Nmm_per_rad / NMM_PER_NM,
            "target_stiffness_Nm_per_rad": self.target_stiffness_Nmm_per_rad / NMM_PER_NM,
            "error_vs_target_pct": 100.0 * self.error_vs_target,
            "fea_vs_beam_pct": 100.0 * (self.stiffness_fea_Nmm_per_rad
                                        / d.stiffness_beam_Nmm_per_rad - 1.0),
            "discretisation_error_pct": 100.0 * run.stiffness_error,
            "tolerance_pct": 100.0 * self.tolerance,
            "peak_von_mises_MPa": self.peak_von_mises_MPa,
            "peak_von_mises_error_pct": 100.0 * run.peak_stress_error,
            "peak_stress_kind": "nodal (element stresses at their quadratic nodes, averaged); "
                                "excludes the held-face zone and the cam contact patch",
            "peak_ip_von_mises_MPa": pr.peak_ip_von_mises_MPa,
            # where: the finest 2D level (the converged field); the 3D check meshes are
            # extrusions of coarser levels, their own location is in check_3d
            "peak_location_mm": list(finest.peak_location_mm),
            "peak_region": finest.peak_region,
            "peak_location_note": f"{st.model} finest level (level {finest.level}); the 3D "
                                  "check's own locations are in check_3d",
            "peak_by_region_MPa": dict(finest.peak_by_region_MPa),
            "peak_by_region_note": f"{st.model} finest level, not extrapolated",
            "max_deflection_rad": d.max_deflection_rad,
            "torque_at_max_deflection_Nm": self.stiffness_fea_Nmm_per_rad * d.max_deflection_rad
            / NMM_PER_NM,
            "design_stress_MPa": d.material.design_stress_MPa,
            "peak_stress_beam_MPa": d.peak_stress_MPa,
            "yield_strength_MPa": self.yield_strength_MPa,
            "yield_margin": self.yield_margin,
            "fatigue": self.fatigue.to_dict() if self.fatigue is not None else None,
            "duty": self.duty_check.to_dict() if self.duty_check is not None else None,
            "duty_points_MPa": self.duty_points_MPa(),
            "contact_fatigue": (self.contact_fatigue.to_dict()
                                if self.contact_fatigue is not None else None),
            "duty_failures": self.duty_failures(),
            "required_safety_factor": self.required_safety_factor,
            "stiffness_ok": self.stiffness_ok,
            "stress_ok": self.stress_ok,
            "ok": self.ok,
            "failures": self.failures(),
            "width_scale": d.width_scale,
            "model": self.model,
            "factor_3d_over_2d": {"stiffness": run.factor_K, "peak_stress": run.factor_stress,
                                  "stiffness_error_pct": 100 * run.factor_K_error,
                                  "peak_stress_error_pct": 100 * run.factor_stress_error},
            "load_case": {"support": self.case.support, "load": self.case.load,
                          "patch_half_angle_deg": math.degrees(self.case.patch_half_angle_rad),
                          "model": "one-flexure sector, free sides, outer rim held"},
            "dofs": finest.dofs,
            "n_elements": finest.n_elements,
            "mesh_quality": q2.quality.to_dict() if q2 is not None else None,
            "convergence": st.to_list(),
            "richardson": st.to_dict(),
            "correction_iterations": list(self.iterations),
            "timings_s": dict(self.timings_s),
            "notes": list(self.notes),
        }
        if self.support is not None:
            out["support_study"] = dict(self.support)
        if self.contact is not None:
            out["contact_sweep"] = self.contact.to_dict()
        if run.check3d:
            c3 = run.check3d[-1]
            out["dofs_3d"] = c3.dofs
            out["n_elements_3d"] = c3.n_elements
            out["mesh_quality_3d"] = c3.mesh.quality.to_dict() if c3.mesh is not None else None
            out["mesh_quality_3d_note"] = (
                "quadratic tets from prisms of the extruded face mesh (upper half, mid-plane "
                "symmetry): long through the thickness by design, where the field varies "
                "slowly; small dihedral angles are that elongation, not slivers. The layer "
                "doubling between the two 3D levels measures its effect (factor error).")
            out["check_3d"] = [{"level": r.level, "dofs": r.dofs,
                                "stiffness_Nm_per_rad": r.stiffness_Nmm_per_rad / NMM_PER_NM,
                                "peak_von_mises_MPa": r.peak_von_mises_MPa,
                                "peak_location_mm": list(r.peak_location_mm)}
                               for r in run.check3d]
        return out


# ================================================================== stacks
@dataclass
class StackVerification:
    """A stack from verified springs: series K and the eq. 10 load case (N*mm, rad, MPa)."""

    sequence: tuple
    stiffness_Nmm_per_rad: float
    target_Nmm_per_rad: float
    max_deflection_rad: float
    torque_at_limit_Nmm: float
    limiting_spring: str
    springs: list
    required_safety_factor: float

    @property
    def ok(self) -> bool:
        return all(s["yield_margin"] >= self.required_safety_factor for s in self.springs)

    def failures(self) -> list[str]:
        return [text for _, text in self.spring_failures()]

    def spring_failures(self) -> list[tuple[str, str]]:
        """(spring name, why) of every spring over its margin at the stack limit."""
        return [(s["spring"], f"stack: spring #{i + 1} ({s['spring']}) at the stack limit "
                 f"{self.max_deflection_rad:.3f} rad carries {s['torque_Nm']:.2f} N*m, peak "
                 f"{s['peak_von_mises_MPa']:.0f} MPa, yield margin {s['yield_margin']:.3f} < "
                 f"{self.required_safety_factor:.3g}")
                for i, s in enumerate(self.springs)
                if s["yield_margin"] < self.required_safety_factor]

    def to_dict(self) -> dict:
        return {"sequence": list(self.sequence),
                "stiffness_fea_Nm_per_rad": self.stiffness_Nmm_per_rad / NMM_PER_NM,
                "target_stiffness_Nm_per_rad": self.target_Nmm_per_rad / NMM_PER_NM,
                "error_vs_target_pct": 100 * (self.stiffness_Nmm_per_rad / self.target_Nmm_per_rad
                                              - 1),
                "max_deflection_rad": self.max_deflection_rad,
                "torque_at_limit_Nm": self.torque_at_limit_Nmm / NMM_PER_NM,
                "limiting_spring": self.limiting_spring,
                "springs": self.springs, "ok": self.ok, "failures": self.failures()}


def verify_stack(sequence, verified: dict, required_safety_factor: float) -> StackVerification:
    """Series stiffness and eq. 10 with FEA stiffnesses; each spring's torque, stress, margin.

    At the stack limit every spring carries the same torque T = min_i(theta_max,i K_i);
    a spring's peak stress scales linearly from its own verified value at its
    maximum deflection: sigma_i = sigma_i(theta_max,i) * T / (K_i theta_max,i).
    """
    ks = [verified[n].stiffness_fea_Nmm_per_rad for n in sequence]
    limits = [verified[n].design.max_deflection_rad for n in sequence]
    limit, torque, shares = eq10_limit(limits, ks)
    springs = []
    for n, k, th_max, th in zip(sequence, ks, limits, shares):
        v = verified[n]
        sigma = v.peak_von_mises_MPa * torque / (k * th_max)
        springs.append({"spring": n, "deflection_rad": th, "fraction_of_own_limit": th / th_max,
                        "torque_Nm": torque / NMM_PER_NM, "peak_von_mises_MPa": sigma,
                        "yield_margin": v.yield_strength_MPa / sigma})
    t = [th * k for th, k in zip(limits, ks)]
    return StackVerification(
        sequence=tuple(sequence), stiffness_Nmm_per_rad=series_stiffness(ks),
        target_Nmm_per_rad=series_stiffness([verified[n].target_stiffness_Nmm_per_rad
                                             for n in sequence]),
        max_deflection_rad=limit, torque_at_limit_Nmm=torque,
        limiting_spring=sequence[t.index(min(t))], springs=springs,
        required_safety_factor=required_safety_factor)


@dataclass(repr=False)
class JobVerification:
    """Every spring of a job verified (and corrected), and the stack."""

    job_name: str
    springs: dict
    stack: StackVerification
    options: VerifyOptions
    timings_s: dict

    @property
    def ok(self) -> bool:
        """Every spring meets its stiffness target and every spring's yield margin in the
        stack's eq. 10 load case meets the required factor (a spring that the stack never
        drives to its own limit is judged at the load it actually carries)."""
        return all(v.stiffness_ok for v in self.springs.values()) and self.stack.ok

    def __repr__(self) -> str:
        return (f"JobVerification({self.job_name!r}, springs={list(self.springs.values())!r}, "
                f"ok={self.ok})")

    def failures(self) -> list[str]:
        out = []
        for v in self.springs.values():
            out += v.stiffness_failures()
        for name, line in self.stack.spring_failures():  # with what the correction tried
            v = self.springs.get(name)
            out.append(line + ("".join(f"; {n}" for n in v.notes if "correction stopped" in n)
                               if v is not None else ""))
        return out

    def notes(self) -> list[str]:
        """Spring-level stress failures that the stack load case does not reach."""
        out = []
        shares = {s["spring"]: s for s in self.stack.springs}
        for n, v in self.springs.items():
            if not v.stress_ok and n in shares and shares[n]["yield_margin"] >= \
                    self.stack.required_safety_factor:
                out.append(f"spring {n} alone, at its own limit, has yield margin "
                           f"{v.yield_margin:.3f} < {v.required_safety_factor:.3g}; in this "
                           f"stack it reaches {100 * shares[n]['fraction_of_own_limit']:.0f} % "
                           f"of that limit (margin {shares[n]['yield_margin']:.3f})")
        return out

    def release_failures(self) -> list[str]:
        """What stops a release without failing the verification: the contact rules at
        +-theta_max of every spring (judged at its own limit, the stack's load at most), or
        that they could not be assessed."""
        out = []
        for n, v in self.springs.items():
            if v.contact is None and self.options.contact:
                out.append(f"spring {n}: the cam contact at +-theta_max was not assessed (the "
                           "contact sweep failed, see the notes)")
            failures = v.contact_failures()
            tried = [t for t in v.notes if t.startswith(CORRECTIONS_TRIED)]
            if failures and tried:  # what the correction tried, and why it was not kept
                failures[-1] += "".join(f"; {one_line(t, 300)}" for t in tried)
            out += failures
        return out

    def duty_failures(self) -> list[str]:
        """What stops a release on the duty: every spring judged at its own theta_max (in a
        stack that drives a spring short of its limit, conservative); the default duty's
        hint (:data:`DEFAULT_DUTY_HINT`) once, after the last."""
        out = [f for v in self.springs.values() for f in v.duty_failures()]
        hinted = [f.endswith(DEFAULT_DUTY_HINT) for f in out]
        out = [f.removesuffix(DEFAULT_DUTY_HINT) for f in out]
        if any(hinted):
            out[-1] += DEFAULT_DUTY_HINT
        return out

    def ratings(self) -> list[str]:
        """One line per spring: what its verified stress field is rated for."""
        out = []
        for n, v in self.springs.items():
            c = v.duty_check
            if c is not None:
                out.append(f"spring {n}: {c.rating_text()} (at the {c.where})")
        return out

    def contact_fatigue_notes(self) -> list[str]:
        """The tip balls' contact fatigue over the duty, one line per spring whose balls
        meet it or are not judged (a shortfall is a duty failure instead)."""
        return [f"spring {n}: {v.contact_fatigue.text()}"
                for n, v in self.springs.items()
                if v.contact_fatigue is not None and not v.contact_fatigue_failures()]

    def raise_for_failures(self) -> None:
        """Raise :class:`VerificationFailed` listing every failure (for ``springcad build``)."""
        if not self.ok:
            raise VerificationFailed("FEA verification failed: " + "; ".join(self.failures()))

    def corrected_designs(self) -> dict:
        """Spring name -> the corrected :class:`SpringDesign` (what ``build`` should export)."""
        return {n: v.design for n, v in self.springs.items()}

    def corrected_job_design(self, job_design):
        """The job design with every spring replaced by its corrected design and the stack
        rebuilt from them (what ``springcad build`` exports after verification): the one
        way, :meth:`~springcad.design.job.JobDesign.with_springs`, so the rim holes stay on
        the job's common circle."""
        return job_design.with_springs(self.corrected_designs())

    def to_dict(self) -> dict:
        return {**stamp(SCHEMA), "job": self.job_name,
                "options": {"model": self.options.model, "levels": self.options.levels,
                            "mesher": self.options.mesher,
                            "tolerance_pct": 100 * self.options.tolerance,
                            "support": self.options.case.support,
                            "load": self.options.case.load},
                "springs": {n: v.to_dict() for n, v in self.springs.items()},
                "stack": self.stack.to_dict(), "ok": self.ok, "failures": self.failures(),
                "release_failures": self.release_failures(),
                "duty_failures": self.duty_failures(), "duty_ratings": self.ratings(),
                "contact_fatigue": self.contact_fatigue_notes(),
                "notes": self.notes(), "timings_s": dict(self.timings_s)}

