"""Design a whole job: every named spring once, then the stack."""

from __future__ import annotations

import math
from dataclasses import dataclass

from springcad.version import __version__
from springcad.config import Job
from springcad.design.plausibility import check_hardware
from springcad.design.search import design_spring
from springcad.design.spring import SpringDesign
from springcad.design.stack import StackDesign, design_stack
from springcad.units import G_PER_KG, MM3_PER_CM3, NMM_PER_NM

SCHEMA = "springcad.design/1"


@dataclass(frozen=True, repr=False)
class JobDesign:
    """Designed springs (by name) and the stack built from them."""

    job: Job
    springs: dict[str, SpringDesign]
    stack: StackDesign

    def __repr__(self) -> str:
        return f"JobDesign({self.job.name!r}, springs={list(self.springs)}, {self.stack!r})"

    def with_springs(self, springs: dict[str, SpringDesign]) -> "JobDesign":
        """The same job with some springs replaced (e.g. FEA-corrected); the stack is redone."""
        merged = common_hole_circle({**self.springs, **springs})
        stack = design_stack([merged[n] for n in self.job.stack.sequence], self.job.stack.input,
                             self.job.analysis.monte_carlo_samples, self.job.analysis.seed)
        return JobDesign(self.job, merged, stack)

    @property
    def warnings(self) -> tuple[str, ...]:
        """Plausibility warnings: the config's and the designed geometry's."""
        from springcad.design.plausibility import design_warnings

        return tuple(self.job.warnings) + tuple(design_warnings(self))

    def notes(self) -> list[str]:
        out = []
        for s in self.springs.values():
            out.extend(f"spring {s.name}: {w}" for w in s.warnings)
        out.extend(self.stack.notes())
        return out

    def release_warnings(self) -> list[str]:
        """Every spring warning and stack warning (the notes that stop a release)."""
        out = [f"spring {s.name}: {w}" for s in self.springs.values() for w in s.warnings]
        return out + self.stack.warnings()

    def to_dict(self) -> dict:
        """The ``design.json`` document (units in key names)."""
        mat = self.job.material
        return {
            "schema": SCHEMA,
            "springcad_version": __version__,
            "job": {"name": self.job.name, "description": self.job.description,
                    "config": self.job.source},
            "material": {
                "name": mat.material.name, "description": mat.material.description,
                "youngs_modulus_MPa": mat.material.youngs_modulus_MPa,
                "poisson_ratio": mat.material.poisson_ratio,
                "yield_strength_MPa": mat.material.yield_strength_MPa,
                "density_kg_per_m3": mat.material.density_kg_per_m3,
                "heat_treatment": mat.material.heat_treatment,
                "design_stress_MPa": mat.design_stress_MPa,
                "safety_factor": mat.safety_factor},
            "manufacturing": {k: getattr(self.job.manufacturing, k) for k in (
                "process", "t_spring_mm", "t_shaft_mm", "w_gap_mm", "wire_diameter_mm",
                "spark_gap_mm", "min_slot_width_mm", "min_web_mm", "min_hole_edge_mm",
                "tolerance_distribution")},
            "springs": {name: s.to_dict() for name, s in self.springs.items()},
            "stack": self.stack.to_dict(),
            "notes": self.notes(),
            "warnings": list(self.warnings),
        }

    def summary(self) -> str:
        """A short plain-text table for the terminal."""
        rows = [("spring", "K N*m/rad", "target", "theta_max deg", "N", "r_c mm", "R_r mm",
                 "tip mm", "flexure", "J/cm3", "J/kg")]
        for s in self.springs.values():
            rows.append((s.name, f"{s.stiffness_beam_Nmm_per_rad / NMM_PER_NM:.2f}",
                         f"{s.target_stiffness_Nmm_per_rad / NMM_PER_NM:.2f}",
                         f"{math.degrees(s.max_deflection_rad):.2f}", str(s.n_flexures),
                         f"{s.contact_radius_mm:.3f}", f"{s.root_radius_mm:.3f}",
                         f"{s.tip_radius_mm:.3f}", s.flexure,
                         f"{s.energy_density_J_per_cm3:.3f}", f"{s.specific_energy_J_per_kg:.1f}"))
        widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
        lines = ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in rows]
        st = self.stack
        b = st.backlash
        lines += [
            "",
            f"stack {' + '.join(st.sequence)}: input {st.input}, output {st.output}, joints "
            f"{', '.join(j + '-to-' + j for j in st.joints) or 'none'}",
            f"  K = {st.stiffness_Nmm_per_rad / NMM_PER_NM:.2f} N*m/rad "
            f"(target {st.target_stiffness_Nmm_per_rad / NMM_PER_NM:.2f}), max deflection "
            f"{st.max_deflection_rad:.3f} rad ({math.degrees(st.max_deflection_rad):.1f} deg, eq. 10)",
            f"  backlash rad: nominal {b.nominal:.4f}, worst [{b.worst_min:.4f}, {b.worst_max:.4f}], "
            f"RSS [{b.rss_min:.4f}, {b.rss_max:.4f}], MC p1-p99 [{b.mc_p01:.4f}, {b.mc_p99:.4f}]",
            f"  energy {st.energy_J:.2f} J, mass {st.mass_kg * G_PER_KG:.1f} g, "
            f"{st.energy_J / (st.envelope_volume_mm3 / MM3_PER_CM3):.3f} J/cm3, "
            f"{st.energy_J / st.mass_kg:.1f} J/kg",
        ]
        for s in self.springs.values():
            fat = s.fatigue
            fat_txt = ("" if fat is None else
                       f", fatigue margin {fat.margin:.2f} at +-{math.degrees(s.max_deflection_rad):.1f} deg"
                       + ("" if fat.margin >= 1 else f" (life {fat.life_cycles:.2g} cycles)"))
            lines.append(
                f"{s.name}: beam stress {s.peak_stress_MPa:.0f} MPa, predicted peak "
                f"{s.predicted_peak_stress_MPa:.0f} MPa at the {s.stress.region if s.stress else '-'}, "
                f"yield margin {s.yield_margin:.3f} (required {s.material.safety_factor:g})"
                f"{fat_txt}, root flare {s.root_flare:g}")
        lines += [f"note: {n}" for n in self.notes()]
        return "\n".join(lines)


def common_hole_circle(springs: dict[str, SpringDesign]) -> dict[str, SpringDesign]:
    """Put the rim holes of every spring on one circle, so any two rims can be pinned.

    The circle is the middle of the thinnest rim: half way between the largest
    root radius and the smallest outer radius (mm).
    """
    from springcad.design.ring import with_hole_circle

    with_holes = [s for s in springs.values() if s.hole_centres_mm]
    if len(with_holes) < 2:
        return springs
    radius = 0.5 * (max(s.root_radius_mm for s in with_holes)
                    + min(s.outer_radius_mm for s in with_holes))
    return {name: with_hole_circle(s, radius) if s.hole_centres_mm else s
            for name, s in springs.items()}


def design_job(job: Job) -> JobDesign:
    """Design every spring named in the job and the stack.

    Raises:
        DesignError: a spring or a hardware part cannot be made as specified.
    """
    springs = {name: design_spring(spec, job.material, job.manufacturing, job.hardware)
               for name, spec in job.springs.items()}
    springs = common_hole_circle(springs)
    stack = design_stack([springs[n] for n in job.stack.sequence], job.stack.input,
                         job.analysis.monte_carlo_samples, job.analysis.seed)
    design = JobDesign(job, springs, stack)
    check_hardware(design)
    return design
