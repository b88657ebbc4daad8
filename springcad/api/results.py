"""Result objects of the public API, in SI units, with short reprs and notebook views.

Each wraps an internal design/analysis type (which works in N*mm and mm) and
exposes the field's units in its names: stiffness in N*m/rad, angles in rad,
stresses in MPa, masses in kg, lengths in mm. ``repr`` is one short line;
``_repr_html_`` (and ``_repr_svg_`` where a drawing says more), what Jupyter shows,
hands over to :mod:`springcad.report.notebook`, and ``summary()``, the terminal's table,
to :mod:`springcad.report.tables`: the results hold data, not HTML or text tables.
"""

from __future__ import annotations

from springcad.options import api_door, check_choice, refuse
from springcad.report import notebook, tables
from springcad.units import NMM_PER_NM as _NMM_PER_NM

__all__ = ["Design", "Fit", "Spring", "Stack", "Verification"]


# --------------------------------------------------------------------------- helpers
def _field(attr: str, doc: str | None = None) -> property:
    """A read-only view of ``self.raw.<attr>`` (same units)."""
    return property(lambda self: getattr(self.raw, attr), doc=doc)


def _torque_Nm(attr: str, doc: str | None = None) -> property:
    """A read-only view of ``self.raw.<attr>`` (N*mm or N*mm/rad) in N*m (or N*m/rad)."""
    return property(lambda self: getattr(self.raw, attr) / _NMM_PER_NM, doc=doc)


# --------------------------------------------------------------------------- results

class Spring:
    """One designed spring, in SI units (wraps :class:`springcad.design.spring.SpringDesign`).

    Attributes:
        raw: the internal design (N*mm, mm).
    """

    def __init__(self, raw):
        self.raw = raw

    name = _field("name")
    n_flexures = _field("n_flexures")
    outer_radius_mm = _field("outer_radius_mm")
    thickness_mm = _field("thickness_mm")
    stiffness_Nm_per_rad = _torque_Nm("stiffness_beam_Nmm_per_rad", "Beam-theory stiffness (N*m/rad).")
    target_stiffness_Nm_per_rad = _torque_Nm("target_stiffness_Nmm_per_rad", "Target stiffness (N*m/rad).")
    max_deflection_rad = _field("max_deflection_rad")
    peak_torque_Nm = _torque_Nm("peak_torque_Nmm", "Torque at the max deflection (N*m).")
    peak_stress_MPa = _field("predicted_peak_stress_MPa", "Predicted peak stress of the real "
                             "geometry at the max deflection (MPa).")
    yield_margin = _field("yield_margin")
    mass_kg = _field("mass_kg")
    energy_density_J_per_cm3 = _field("energy_density_J_per_cm3")

    def to_dict(self) -> dict:
        """The ``design.json`` entry (units in key names)."""
        return self.raw.to_dict()

    def __repr__(self) -> str:
        return (f"Spring({self.name!r}: K={self.stiffness_Nm_per_rad:.4g} N*m/rad "
                f"(target {self.target_stiffness_Nm_per_rad:.4g}), "
                f"theta_max={self.max_deflection_rad:.4g} rad, N={self.n_flexures}, "
                f"peak {self.peak_stress_MPa:.0f} MPa, mass {self.mass_kg:.4g} kg)")

    def _repr_svg_(self) -> str:
        return notebook.profile_svg(self.raw)

    def _repr_html_(self) -> str:
        return notebook.spring_html(self)


class Stack:
    """The series stack, in SI units (wraps :class:`springcad.design.stack.StackDesign`)."""

    def __init__(self, raw):
        self.raw = raw

    sequence = _field("sequence")
    limiting_spring = _field("limiting_spring")
    mass_kg = _field("mass_kg")
    energy_J = _field("energy_J")
    stiffness_Nm_per_rad = _torque_Nm("stiffness_Nmm_per_rad", "Beam-theory stiffness (N*m/rad).")
    target_stiffness_Nm_per_rad = _torque_Nm("target_stiffness_Nmm_per_rad", "Target stiffness (N*m/rad).")
    max_deflection_rad = _field("max_deflection_rad", "The eq. 10 stack limit (rad).")

    @property
    def backlash_nominal_rad(self) -> float:
        return self.raw.backlash.nominal

    @property
    def backlash_worst_range_rad(self) -> tuple[float, float]:
        return (self.raw.backlash.worst_min, self.raw.backlash.worst_max)

    def to_dict(self) -> dict:
        return self.raw.to_dict()

    def __repr__(self) -> str:
        return (f"Stack({' + '.join(self.sequence)}: K={self.stiffness_Nm_per_rad:.4g} N*m/rad, "
                f"limit {self.max_deflection_rad:.4g} rad ({self.limiting_spring}), backlash "
                f"{self.backlash_nominal_rad:.4g} rad, mass {self.mass_kg:.4g} kg)")

    def _repr_svg_(self) -> str:
        return notebook.stack_svg(self.raw)

    def _repr_html_(self) -> str:
        return notebook.stack_html(self)


class Design:
    """A designed job: its springs and stack (wraps :class:`springcad.design.job.JobDesign`).

    Attributes:
        raw: the internal job design.
        springs: spring name -> :class:`Spring`.
        stack: the :class:`Stack`.
    """

    def __init__(self, raw):
        self.raw = raw
        self.springs = {n: Spring(s) for n, s in raw.springs.items()}
        self.stack = Stack(raw.stack)

    @property
    def job(self):
        return self.raw.job

    @property
    def warnings(self) -> tuple[str, ...]:
        return tuple(self.raw.warnings)

    def to_dict(self) -> dict:
        """The ``design.json`` document."""
        return self.raw.to_dict()

    def summary(self) -> str:
        """A short plain-text table: the springs, the stack, the duty and the notes
        (what ``springcad design`` prints; :func:`springcad.report.tables.design_table`)."""
        return tables.design_table(self.raw)

    def __repr__(self) -> str:
        return (f"Design({self.job.name!r}: {len(self.springs)} spring(s) "
                f"{', '.join(self.springs)}; {self.stack!r})")

    def _repr_html_(self) -> str:
        return notebook.design_html(self)


class Verification:
    """FEA verification of a job (wraps :class:`fea.verdict.JobVerification`).

    Attributes:
        raw: the internal result (N*mm).
        design: the verified (width-corrected) :class:`Design`.
    """

    def __init__(self, raw, design: Design):
        self.raw = raw
        self._input = design
        self._design = None

    @property
    def job(self):
        """The :class:`~springcad.config.Job` that was verified."""
        return self._input.job

    @property
    def design(self) -> Design:
        """The verified design: the input with the FEA-corrected springs (made on first use)."""
        if self._design is None:
            self._design = Design(self.raw.corrected_job_design(self._input.raw))
        return self._design

    @property
    def ok(self) -> bool:
        return self.raw.ok

    def failures(self) -> list[str]:
        return self.raw.failures()

    def raise_for_failures(self) -> None:
        """Raises :class:`fea.verdict.VerificationFailed` (a
        :class:`~springcad.errors.CheckFailed`) listing every failure, if any."""
        self.raw.raise_for_failures()

    def spring_table(self) -> list[dict]:
        """Per spring: FEA and beam stiffness (N*m/rad), errors (%), peak stress (MPa), margins."""
        out = []
        for n, v in self.raw.springs.items():
            out.append({"spring": n,
                        "stiffness_fea_Nm_per_rad": v.stiffness_fea_Nmm_per_rad / _NMM_PER_NM,
                        "stiffness_beam_Nm_per_rad": v.design.stiffness_beam_Nmm_per_rad / _NMM_PER_NM,
                        "target_stiffness_Nm_per_rad": v.target_stiffness_Nmm_per_rad / _NMM_PER_NM,
                        "error_vs_target_pct": 100 * v.error_vs_target,
                        "discretisation_error_pct": 100 * v.run.stiffness_error,
                        "peak_von_mises_MPa": v.peak_von_mises_MPa,
                        "peak_stress_design_MPa": v.design.predicted_peak_stress_MPa,
                        "yield_margin": v.yield_margin, "ok": v.ok})
        return out

    @property
    def stack_stiffness_Nm_per_rad(self) -> float:
        return self.raw.stack.stiffness_Nmm_per_rad / _NMM_PER_NM

    @api_door
    def field(self, spring: str, model: str = "finest"):
        """The FE field of one spring at its maximum deflection, as plain arrays.

        Args:
            spring: the spring's name.
            model: "finest" (the finest mesh of the convergence study, in the verified
                model) or "3d" (the 3D check, when it ran).

        Returns:
            A :class:`fea.results.Field`: ``points_mm`` (n, 3), ``cells`` (quadratic,
            VTK node order), ``displacement_mm`` (n, 3), ``von_mises_MPa`` (n,),
            ``excluded`` (n,) (mm, MPa).

        Raises:
            OptionError: an unknown spring or model, or a 3D field that was not computed.
            ValueError: the verification kept no fields.
        """
        check_choice("spring", spring, tuple(self.raw.springs))
        check_choice("model", model, ("finest", "3d"))
        run = self.raw.springs[spring].run
        if model == "finest":
            return run.study.finest.field
        if not run.check3d:
            raise refuse("model", model, "needs the 3D check, which this verification did not run")
        return run.check3d[-1].field

    def to_dict(self) -> dict:
        """The ``fea.json`` document."""
        return self.raw.to_dict()

    def summary(self) -> str:
        """A short plain-text table: per spring FEA vs beam stiffness, stresses and margins,
        the stack, ratings, failures and contact findings (what ``springcad verify``
        prints; :func:`springcad.report.tables.verification_table`)."""
        return tables.verification_table(self.raw)

    def __repr__(self) -> str:
        parts = ", ".join(f"{r['spring']}: K_fea {r['stiffness_fea_Nm_per_rad']:.4g} N*m/rad "
                          f"({r['error_vs_target_pct']:+.2f} %), {r['peak_von_mises_MPa']:.0f} MPa"
                          for r in self.spring_table())
        return (f"Verification({'ok' if self.ok else 'FAILED'}; {parts}; stack K_fea "
                f"{self.stack_stiffness_Nm_per_rad:.4g} N*m/rad)")

    def _repr_html_(self) -> str:
        return notebook.verification_html(self)


class Fit:
    """A fitted bench record (wraps :class:`springcad.fit.analysis.FitResult`).

    The summary is held as fields, taken once from the fit (not read back from its
    ``fit.json`` document, which :meth:`to_dict` writes).

    Attributes:
        raw: the internal result.
        design_warnings: plausibility warnings of the design the fit was compared with.
        model: the final model in words (``"linear + backlash + ..."``).
        stiffness_Nm_per_rad: final-model stiffness (N*m/rad); the deadband fit's when no
            spring was found.
        backlash_rad: the paper's deadband-model backlash (rad).
        nrmse_pct: the final model's NRMSE (% of half the measured torque range).
    """

    def __init__(self, raw, design_warnings: tuple[str, ...] = ()):
        self.raw = raw
        self.design_warnings = tuple(design_warnings)
        self.model = raw.final_model
        self.stiffness_Nm_per_rad = raw.stiffness_Nm_per_rad
        self.backlash_rad = raw.paper_models["deadband"].backlash_rad
        self.nrmse_pct = raw.nrmse_pct(raw.loop.final)

    @property
    def warnings(self) -> tuple[str, ...]:
        """The design's plausibility warnings, then the record's (units, magnitudes)."""
        return self.design_warnings + tuple(self.raw.record.warnings)

    def to_dict(self) -> dict:
        """The ``fit.json`` document."""
        return self.raw.to_dict()

    def effects(self) -> list[dict]:
        """The residual loop's steps: effect, action, NRMSE before and after (%)."""
        return [{"effect": s.effect, "action": s.action, "nrmse_before_pct": s.nrmse_before_pct,
                 "nrmse_after_pct": s.nrmse_after_pct} for s in self.raw.loop.steps]

    def __repr__(self) -> str:
        chain = " ".join(f"{'+' if e['action'] == 'add' else '-' if e['action'] == 'remove' else 'x'}"
                         f"{e['effect']}" for e in self.effects()) or "no effects"
        return (f"Fit({self.raw.record.source}: {self.model}, K={self.stiffness_Nm_per_rad:.4g} "
                f"N*m/rad, backlash {self.backlash_rad:.4g} rad, NRMSE {self.nrmse_pct:.3g} %; "
                f"{chain})")

    def plot_png(self) -> bytes:
        """The torque-deflection plot (data and models) as PNG bytes."""
        return notebook.fit_png(self)

    def _repr_html_(self) -> str:
        return notebook.fit_html(self)
