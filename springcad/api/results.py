"""Result objects of the public API, in SI units, with short reprs and notebook views.

Each wraps an internal design/analysis type (which works in N*mm and mm) and
exposes the field's units in its names: stiffness in N*m/rad, angles in rad,
stresses in MPa, masses in kg, lengths in mm. ``repr`` is one short line;
``_repr_html_`` (and ``_repr_svg_`` where a drawing says more) is what
Jupyter shows.
"""

from __future__ import annotations

import base64
import html
from pathlib import Path

from springcad.units import NMM_PER_NM as _NMM_PER_NM

__all__ = ["Design", "Fit", "Spring", "Stack", "Verification"]


# --------------------------------------------------------------------------- helpers
def _field(attr: str, doc: str | None = None) -> property:
    """A read-only view of ``self.raw.<attr>`` (same units)."""
    return property(lambda self: getattr(self.raw, attr), doc=doc)


def _torque_Nm(attr: str, doc: str | None = None) -> property:
    """A read-only view of ``self.raw.<attr>`` (N*mm or N*mm/rad) in N*m (or N*m/rad)."""
    return property(lambda self: getattr(self.raw, attr) / _NMM_PER_NM, doc=doc)


def _table_html(rows: list[tuple[str, str]], caption: str = "") -> str:
    cap = f"<caption style='text-align:left'><b>{html.escape(caption)}</b></caption>" if caption else ""
    body = "".join(f"<tr><td style='text-align:left'>{html.escape(k)}</td>"
                   f"<td style='text-align:right'>{html.escape(v)}</td></tr>" for k, v in rows)
    return f"<table>{cap}{body}</table>"


def _grid_html(header: tuple, rows: list[tuple]) -> str:
    head = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>"
                   for r in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _g(v: float | None, digits: int = 4) -> str:
    return "-" if v is None else f"{v:.{digits}g}"


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
        return profile_svg(self.raw)

    def _repr_html_(self) -> str:
        rows = [("stiffness (N·m/rad)", _g(self.stiffness_Nm_per_rad)),
                ("target (N·m/rad)", _g(self.target_stiffness_Nm_per_rad)),
                ("max deflection (rad)", _g(self.max_deflection_rad)),
                ("peak torque (N·m)", _g(self.peak_torque_Nm)),
                ("predicted peak stress (MPa)", f"{self.peak_stress_MPa:.0f}"),
                ("yield margin", f"{self.yield_margin:.3f}"),
                ("flexures", str(self.n_flexures)),
                ("outer radius (mm)", _g(self.outer_radius_mm)),
                ("mass (kg)", _g(self.mass_kg)),
                ("energy density (J/cm³)", _g(self.energy_density_J_per_cm3))]
        return (f"<div style='display:flex;gap:1em;align-items:flex-start'>"
                f"<div>{profile_svg(self.raw, size_px=220)}</div>"
                f"<div>{_table_html(rows, f'spring {self.name}')}</div></div>")


def profile_svg(raw, size_px: int = 300) -> str:
    """An inline SVG of a spring's ring and cam profiles (mm, y up).

    Args:
        raw: a :class:`~springcad.design.spring.SpringDesign` with its profiles.
        size_px: width and height of the drawing (px).
    """
    from springcad.design.planar import sample_profile

    loops = []
    for profile, colour in ((raw.ring, "#4a6fa5"), (raw.cam, "#c0504d")):
        if profile is None:
            continue
        for s in sample_profile(profile, step_mm=max(raw.outer_radius_mm / 400, 0.02)):
            loops.append((s.points, colour))
    r = raw.outer_radius_mm * 1.05
    paths = []
    for pts, colour in loops:
        d = " ".join(f"{'M' if i == 0 else 'L'}{x:.3f},{-y:.3f}" for i, (x, y) in enumerate(pts))
        paths.append(f"<path d='{d} Z' fill='none' stroke='{colour}' stroke-width='{r / 250:.4f}'/>")
    return (f"<svg xmlns='http://www.w3.org/2000/svg' width='{size_px}' height='{size_px}' "
            f"viewBox='{-r:.3f} {-r:.3f} {2 * r:.3f} {2 * r:.3f}'>"
            f"<title>spring {html.escape(raw.name)} profile (ring blue, cam red)</title>"
            + "".join(paths) + "</svg>")


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
        return stack_svg(self.raw)

    def _repr_html_(self) -> str:
        lo, hi = self.backlash_worst_range_rad
        b = self.raw.backlash
        rows = [("sequence", " + ".join(self.sequence)),
                ("input / output", f"{self.raw.input} / {self.raw.output}"),
                ("stiffness (N·m/rad)", _g(self.stiffness_Nm_per_rad)),
                ("target (N·m/rad)", _g(self.target_stiffness_Nm_per_rad)),
                ("max deflection, eq. 10 (rad)", _g(self.max_deflection_rad)),
                ("limiting spring", str(self.limiting_spring)),
                ("backlash nominal (rad)", _g(self.backlash_nominal_rad)),
                ("backlash worst case (rad)", f"{lo:.4g} … {hi:.4g}"),
                ("backlash MC p1–p99 (rad)", f"{b.mc_p01:.4g} … {b.mc_p99:.4g}"),
                ("mass (kg)", _g(self.mass_kg)),
                ("energy (J)", _g(self.energy_J))]
        return (f"<div>{stack_svg(self.raw)}{_table_html(rows, 'stack')}</div>")


def stack_svg(raw, box_px: int = 110) -> str:
    """An inline SVG of a stack: input -> springs in series -> output, the limiting one red.

    Each spring box gives its stiffness (N*m/rad) and its own deflection limit
    (rad); the caption gives the stack's stiffness and eq. 10 limit.

    Args:
        raw: a :class:`~springcad.design.stack.StackDesign`.
        box_px: width of one spring box (px).
    """
    springs = list(raw.springs)
    gap, h, end = 28, 64, 70
    items = [(f"<rect x='4' y='20' width='{end - 8}' height='{h}' rx='8' fill='#dcefe0' "
              f"stroke='#2e7d32'/><text x='{end / 2}' y='56' text-anchor='middle'>input</text>"
              f"<text x='{end / 2}' y='72' text-anchor='middle' font-size='10'>"
              f"{html.escape(str(raw.input))}</text>")]
    x = end + gap
    for sp in springs:
        limiting = sp.name == raw.limiting_spring
        colour = "#b8322a" if limiting else "#4a6fa5"
        items.append(
            f"<line x1='{x - gap}' y1='52' x2='{x}' y2='52' stroke='#555' stroke-width='2'/>"
            f"<rect x='{x}' y='20' width='{box_px}' height='{h}' rx='6' fill='#f4f6fb' "
            f"stroke='{colour}' stroke-width='{3 if limiting else 1.5}'/>"
            f"<text x='{x + box_px / 2}' y='38' text-anchor='middle' font-weight='bold'>"
            f"{html.escape(sp.name)}</text>"
            f"<text x='{x + box_px / 2}' y='55' text-anchor='middle' font-size='11'>"
            f"{sp.stiffness_beam_Nmm_per_rad / _NMM_PER_NM:.4g} N·m/rad</text>"
            f"<text x='{x + box_px / 2}' y='72' text-anchor='middle' font-size='11' "
            f"fill='{colour}'>θmax {sp.max_deflection_rad:.3g} rad</text>")
        x += box_px + gap
    items.append(f"<line x1='{x - gap}' y1='52' x2='{x}' y2='52' stroke='#555' stroke-width='2'/>"
                 f"<rect x='{x}' y='20' width='{end - 8}' height='{h}' rx='8' fill='#fbe6dc' "
                 f"stroke='#c0504d'/><text x='{x + (end - 8) / 2}' y='56' text-anchor='middle'>"
                 f"output</text><text x='{x + (end - 8) / 2}' y='72' text-anchor='middle' "
                 f"font-size='10'>{html.escape(str(raw.output))}</text>")
    caption = (f"series: K = {raw.stiffness_Nmm_per_rad / _NMM_PER_NM:.4g} N·m/rad, limit "
               f"{raw.max_deflection_rad:.4g} rad (eq. 10, set by {raw.limiting_spring})")
    total_w = x + end
    return (f"<svg xmlns='http://www.w3.org/2000/svg' width='{max(total_w, 360)}' height='110' "
            f"font-family='sans-serif' font-size='12'><title>stack {html.escape(' + '.join(raw.sequence))}"
            f"</title>{''.join(items)}<text x='4' y='102'>{html.escape(caption)}</text></svg>")


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

    def __repr__(self) -> str:
        return (f"Design({self.job.name!r}: {len(self.springs)} spring(s) "
                f"{', '.join(self.springs)}; {self.stack!r})")

    def _repr_html_(self) -> str:
        springs = "".join(s._repr_html_() for s in self.springs.values())
        warn = "".join(f"<li>{html.escape(w)}</li>" for w in self.warnings)
        return (f"<div><h4>design {html.escape(self.job.name)}</h4>{self.stack._repr_html_()}"
                f"{springs}{'<ul>' + warn + '</ul>' if warn else ''}</div>")


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
                        "stiffness_target_Nm_per_rad": v.stiffness_target_Nmm_per_rad / _NMM_PER_NM,
                        "error_vs_target_pct": 100 * v.error_vs_target,
                        "discretisation_error_pct": 100 * v.run.stiffness_error,
                        "peak_von_mises_MPa": v.peak_von_mises_MPa,
                        "peak_stress_design_MPa": v.design.predicted_peak_stress_MPa,
                        "yield_margin": v.yield_margin, "ok": v.ok})
        return out

    @property
    def stack_stiffness_Nm_per_rad(self) -> float:
        return self.raw.stack.stiffness_Nmm_per_rad / _NMM_PER_NM

    def to_dict(self) -> dict:
        """The ``fea.json`` document."""
        return self.raw.to_dict()

    def __repr__(self) -> str:
        parts = ", ".join(f"{r['spring']}: K_fea {r['stiffness_fea_Nm_per_rad']:.4g} N*m/rad "
                          f"({r['error_vs_target_pct']:+.2f} %), {r['peak_von_mises_MPa']:.0f} MPa"
                          for r in self.spring_table())
        return (f"Verification({'ok' if self.ok else 'FAILED'}; {parts}; stack K_fea "
                f"{self.stack_stiffness_Nm_per_rad:.4g} N*m/rad)")

    def _repr_html_(self) -> str:
        rows = [(r["spring"], _g(r["stiffness_fea_Nm_per_rad"]), _g(r["stiffness_beam_Nm_per_rad"]),
                 _g(r["stiffness_target_Nm_per_rad"]), f"{r['error_vs_target_pct']:+.2f}",
                 f"{r['discretisation_error_pct']:.3f}", f"{r['peak_von_mises_MPa']:.0f}",
                 f"{r['peak_stress_design_MPa']:.0f}", f"{r['yield_margin']:.3f}",
                 "yes" if r["ok"] else "NO") for r in self.spring_table()]
        fails = "".join(f"<li>{html.escape(f)}</li>" for f in self.failures())
        verdict = "verified" if self.ok else "FAILED"
        return (f"<div><h4>FEA verification: {verdict}</h4>"
                + _grid_html(("spring", "K FEA N·m/rad", "K beam", "target", "err %", "disc. %",
                              "σ FEA MPa", "σ design MPa", "yield margin", "ok"), rows)
                + (f"<ul>{fails}</ul>" if fails else "") + "</div>")


class Fit:
    """A fitted bench record (wraps :class:`springcad.fit.analysis.FitResult`).

    Attributes:
        raw: the internal result.
        design_warnings: plausibility warnings of the design the fit was compared with.
    """

    def __init__(self, raw, design_warnings: tuple[str, ...] = ()):
        self.raw = raw
        self.design_warnings = tuple(design_warnings)
        self._dict = None

    @property
    def warnings(self) -> tuple[str, ...]:
        """The design's plausibility warnings, then the record's (units, magnitudes)."""
        return self.design_warnings + tuple(self.raw.record.warnings)

    def to_dict(self) -> dict:
        """The ``fit.json`` document."""
        if self._dict is None:
            self._dict = self.raw.to_dict()
        return self._dict

    @property
    def model(self) -> str:
        return self.to_dict()["final"]["model"]

    @property
    def stiffness_Nm_per_rad(self) -> float:
        """Final-model stiffness (N*m/rad); the deadband fit's when no spring was found."""
        d = self.to_dict()
        ci = d["final"].get("intervals", {}).get("stiffness_Nm_per_rad")
        return ci["value"] if ci else d["paper_models"]["deadband"]["stiffness_Nm_per_rad"]

    @property
    def backlash_rad(self) -> float:
        """The paper's deadband-model backlash (rad)."""
        return self.to_dict()["paper_models"]["deadband"]["backlash_rad"]

    @property
    def nrmse_pct(self) -> float:
        return self.to_dict()["final"]["nrmse_pct"]

    def effects(self) -> list[dict]:
        """The residual loop's steps: effect, action, NRMSE before and after (%)."""
        return [{"effect": s["effect"], "action": s["action"],
                 "nrmse_before_pct": s.get("nrmse_before_pct"),
                 "nrmse_after_pct": s["nrmse_after_pct"]} for s in self.to_dict()["steps"]]

    def __repr__(self) -> str:
        chain = " ".join(f"{'+' if e['action'] == 'add' else '-' if e['action'] == 'remove' else 'x'}"
                         f"{e['effect']}" for e in self.effects()) or "no effects"
        return (f"Fit({self.raw.record.source}: {self.model}, K={self.stiffness_Nm_per_rad:.4g} "
                f"N*m/rad, backlash {self.backlash_rad:.4g} rad, NRMSE {self.nrmse_pct:.3g} %; "
                f"{chain})")

    def plot_png(self) -> bytes:
        """The torque-deflection plot (data and models) as PNG bytes."""
        import tempfile

        from springcad.report.fit_plots import _plot_models
        from springcad.report.mpl import pyplot as _pyplot

        plt = _pyplot()
        with tempfile.TemporaryDirectory() as tmp:
            path = _plot_models(plt, self.raw, Path(tmp) / "torque_deflection.png", zoom=False)
            return path.read_bytes()

    def _repr_html_(self) -> str:
        d = self.to_dict()
        rows = [(name, _g(m["stiffness_Nm_per_rad"]), _g(m["backlash_rad"]), f"{m['nrmse_pct']:.3g}")
                for name, m in d["paper_models"].items()]
        eff = [(e["effect"], e["action"], _g(e["nrmse_before_pct"], 3), _g(e["nrmse_after_pct"], 3))
               for e in self.effects()]
        img = base64.b64encode(self.plot_png()).decode("ascii")
        return (f"<div><h4>fit of {html.escape(str(self.raw.record.source))}</h4>"
                f"<img alt='torque against deflection' src='data:image/png;base64,{img}' width='480'/>"
                + _grid_html(("model", "K N·m/rad", "b rad", "NRMSE %"), rows)
                + (_grid_html(("effect", "action", "NRMSE before %", "NRMSE after %"), eff)
                   if eff else "<p>no effect added to the linear model</p>")
                + f"<p>final: {html.escape(self.model)}, K = {self.stiffness_Nm_per_rad:.4g} N·m/rad,"
                  f" NRMSE {self.nrmse_pct:.3g} %</p></div>")
