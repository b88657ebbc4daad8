"""Notebook views of the API's results: HTML tables, inline SVG drawings, PNG plots.

The result objects of :mod:`springcad.api.results` are data; their ``_repr_html_`` and
``_repr_svg_`` (what Jupyter shows) hand over to the functions here, as build123d's
shapes hand their display to ``jupyter_tools``. Units as in the results: N*m/rad, rad,
MPa, kg, mm.
"""

from __future__ import annotations

import base64
import html
from pathlib import Path

from springcad.report.html_page import img_tag
from springcad.report.mpl import pyplot
from springcad.units import NMM_PER_NM


def table_html(rows: list[tuple[str, str]], caption: str = "") -> str:
    """A two-column HTML table (name, value) with an optional caption."""
    cap = f"<caption style='text-align:left'><b>{html.escape(caption)}</b></caption>" if caption else ""
    body = "".join(f"<tr><td style='text-align:left'>{html.escape(k)}</td>"
                   f"<td style='text-align:right'>{html.escape(v)}</td></tr>" for k, v in rows)
    return f"<table>{cap}{body}</table>"


def grid_html(header: tuple, rows: list[tuple]) -> str:
    """An HTML table with a header row."""
    head = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>"
                   for r in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def g(v: float | None, digits: int = 4) -> str:
    """A number with ``digits`` significant digits, "-" for None."""
    return "-" if v is None else f"{v:.{digits}g}"




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
            f"{sp.stiffness_beam_Nmm_per_rad / NMM_PER_NM:.4g} N·m/rad</text>"
            f"<text x='{x + box_px / 2}' y='72' text-anchor='middle' font-size='11' "
            f"fill='{colour}'>θmax {sp.max_deflection_rad:.3g} rad</text>")
        x += box_px + gap
    items.append(f"<line x1='{x - gap}' y1='52' x2='{x}' y2='52' stroke='#555' stroke-width='2'/>"
                 f"<rect x='{x}' y='20' width='{end - 8}' height='{h}' rx='8' fill='#fbe6dc' "
                 f"stroke='#c0504d'/><text x='{x + (end - 8) / 2}' y='56' text-anchor='middle'>"
                 f"output</text><text x='{x + (end - 8) / 2}' y='72' text-anchor='middle' "
                 f"font-size='10'>{html.escape(str(raw.output))}</text>")
    caption = (f"series: K = {raw.stiffness_Nmm_per_rad / NMM_PER_NM:.4g} N·m/rad, limit "
               f"{raw.max_deflection_rad:.4g} rad (eq. 10, set by {raw.limiting_spring})")
    total_w = x + end
    return (f"<svg xmlns='http://www.w3.org/2000/svg' width='{max(total_w, 360)}' height='110' "
            f"font-family='sans-serif' font-size='12'><title>stack {html.escape(' + '.join(raw.sequence))}"
            f"</title>{''.join(items)}<text x='4' y='102'>{html.escape(caption)}</text></svg>")


def spring_html(obj) -> str:
    """A spring's profile drawing and its table (an API :class:`~springcad.api.results.Spring`)."""
    rows = [("stiffness (N·m/rad)", g(obj.stiffness_Nm_per_rad)),
            ("target (N·m/rad)", g(obj.target_stiffness_Nm_per_rad)),
            ("max deflection (rad)", g(obj.max_deflection_rad)),
            ("peak torque (N·m)", g(obj.peak_torque_Nm)),
            ("predicted peak stress (MPa)", f"{obj.peak_stress_MPa:.0f}"),
            ("yield margin", f"{obj.yield_margin:.3f}"),
            ("flexures", str(obj.n_flexures)),
            ("outer radius (mm)", g(obj.outer_radius_mm)),
            ("mass (kg)", g(obj.mass_kg)),
            ("energy density (J/cm³)", g(obj.energy_density_J_per_cm3))]
    return (f"<div style='display:flex;gap:1em;align-items:flex-start'>"
            f"<div>{profile_svg(obj.raw, size_px=220)}</div>"
            f"<div>{table_html(rows, f'spring {obj.name}')}</div></div>")


def stack_html(obj) -> str:
    """A stack's series drawing and its table (an API :class:`~springcad.api.results.Stack`)."""
    lo, hi = obj.backlash_worst_range_rad
    b = obj.raw.backlash
    rows = [("sequence", " + ".join(obj.sequence)),
            ("input / output", f"{obj.raw.input} / {obj.raw.output}"),
            ("stiffness (N·m/rad)", g(obj.stiffness_Nm_per_rad)),
            ("target (N·m/rad)", g(obj.target_stiffness_Nm_per_rad)),
            ("max deflection, eq. 10 (rad)", g(obj.max_deflection_rad)),
            ("limiting spring", str(obj.limiting_spring)),
            ("backlash nominal (rad)", g(obj.backlash_nominal_rad)),
            ("backlash worst case (rad)", f"{lo:.4g} … {hi:.4g}"),
            ("backlash MC p1–p99 (rad)", f"{b.mc_p01:.4g} … {b.mc_p99:.4g}"),
            ("mass (kg)", g(obj.mass_kg)),
            ("energy (J)", g(obj.energy_J))]
    return (f"<div>{stack_svg(obj.raw)}{table_html(rows, 'stack')}</div>")


def design_html(obj) -> str:
    """A design: its stack, every spring and the warnings (an API ``Design``)."""
    springs = "".join(spring_html(s) for s in obj.springs.values())
    warn = "".join(f"<li>{html.escape(w)}</li>" for w in obj.warnings)
    return (f"<div><h4>design {html.escape(obj.job.name)}</h4>{stack_html(obj.stack)}"
            f"{springs}{'<ul>' + warn + '</ul>' if warn else ''}</div>")


def verification_html(obj) -> str:
    """The FEA verification table and its failures (an API ``Verification``)."""
    rows = [(r["spring"], g(r["stiffness_fea_Nm_per_rad"]), g(r["stiffness_beam_Nm_per_rad"]),
             g(r["target_stiffness_Nm_per_rad"]), f"{r['error_vs_target_pct']:+.2f}",
             f"{r['discretisation_error_pct']:.3f}", f"{r['peak_von_mises_MPa']:.0f}",
             f"{r['peak_stress_design_MPa']:.0f}", f"{r['yield_margin']:.3f}",
             "yes" if r["ok"] else "NO") for r in obj.spring_table()]
    fails = "".join(f"<li>{html.escape(f)}</li>" for f in obj.failures())
    verdict = "verified" if obj.ok else "FAILED"
    return (f"<div><h4>FEA verification: {verdict}</h4>"
            + grid_html(("spring", "K FEA N·m/rad", "K beam", "target", "err %", "disc. %",
                          "σ FEA MPa", "σ design MPa", "yield margin", "ok"), rows)
            + (f"<ul>{fails}</ul>" if fails else "") + "</div>")


def fit_png(obj) -> bytes:
    """The torque-deflection plot of a fit (data and models) as PNG bytes (an API ``Fit``)."""
    import tempfile

    # matplotlib (behind these) only when a plot is drawn: ``import springcad`` stays light
    from springcad.report.fit_plots import _plot_models

    plt = pyplot()
    with tempfile.TemporaryDirectory() as tmp:
        path = _plot_models(plt, obj.raw, Path(tmp) / "torque_deflection.png", zoom=False)
        return path.read_bytes()


def fit_html(obj) -> str:
    """A fit: the plot, the paper models and the residual loop's steps (an API ``Fit``)."""
    rows = [(name, g(m.stiffness_Nm_per_rad), g(m.backlash_rad), f"{m.nrmse_pct:.3g}")
            for name, m in obj.raw.paper_models.items()]
    eff = [(e["effect"], e["action"], g(e["nrmse_before_pct"], 3), g(e["nrmse_after_pct"], 3))
           for e in obj.effects()]
    img = base64.b64encode(fit_png(obj)).decode("ascii")
    return (f"<div><h4>fit of {html.escape(str(obj.raw.record.source))}</h4>"
            f"<img alt='torque against deflection' src='data:image/png;base64,{img}' width='480'/>"
            + grid_html(("model", "K N·m/rad", "b rad", "NRMSE %"), rows)
            + (grid_html(("effect", "action", "NRMSE before %", "NRMSE after %"), eff)
               if eff else "<p>no effect added to the linear model</p>")
            + f"<p>final: {html.escape(obj.model)}, K = {obj.stiffness_Nm_per_rad:.4g} N·m/rad,"
              f" NRMSE {obj.nrmse_pct:.3g} %</p></div>")


def build_html(obj) -> str:
    """A build: stiffness, checks, release, the assembly render and the parts (an API ``Build``)."""
    rows = [("stack stiffness (N·m/rad)", g(obj.stiffness_Nm_per_rad)),
            ("from", "FEA" if obj.verification is not None else "beam theory (not verified)"),
            ("deflection limit (rad)", g(obj.max_deflection_rad)),
            ("spring mass (kg)", g(obj.mass_kg)),
            ("checks", obj.checks.summary()),
            ("release", obj.release.stamp if obj.release is not None else "not exported"),
            ("folder", str(obj.out_dir) if obj.out_dir is not None else "–")]
    parts = [(p["part_number"], p["quantity"], p["title"], p["process"]) for p in obj.parts()]
    fails = "".join(f"<li>{html.escape(f)}</li>" for f in obj.failures())
    reasons = "".join(f"<li>{html.escape(r)}</li>" for r in
                      (obj.release.reasons if obj.release is not None else ()))
    render = obj.out_dir / "assembly.png" if obj.out_dir is not None else None
    if render is not None and render.is_file():
        picture = img_tag(render, "assembly render", width=480)
    else:
        picture = ""
    return (f"<div><h4>build {html.escape(obj.design.job.name)}</h4>{picture}"
            + table_html(rows) + (f"<p>failed checks:</p><ul>{fails}</ul>" if fails else "")
            + (f"<p>not for manufacture because:</p><ul>{reasons}</ul>" if reasons else "")
            + grid_html(("part", "qty", "title", "process"), parts) + "</div>")
