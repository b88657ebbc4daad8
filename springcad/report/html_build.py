"""``report.html`` of a build folder: one self-contained page a person reads or sends.

The page is rendered from the files the build wrote (``build.json``,
``design.json``, ``fea/fea.json``, ``bom.csv``, the PNG renders and the
drawings); it computes no physics. Images are inlined as base64 data, so the
page needs no network and no neighbouring files except the PDFs its drawing
thumbnails link to. Order: the verdict (released or not for manufacture, and
why), the spec-vs-achieved table, warnings, FEA images and the contact curve,
the assembly render, the drawings, the bill of materials.
"""

from __future__ import annotations

import csv
import html
import io
import json
import math
from pathlib import Path

from springcad.options import written
from springcad.report.html_page import img_tag as _img
from springcad.report.html_page import page

#: headings every report has, in order (tests look for them)
SECTIONS = ("Verdict", "Spec vs achieved", "Duty", "Warnings", "FEA", "Assembly", "Drawings",
            "Bill of materials")
#: shown above each group of figures on a narrow (phone) screen only: the plots are drawn
#: for a desktop page
NARROW_NOTE = ("Desktop figures: their labels are small on a phone; zoom in, or open "
               "report.html on a wide screen.")


def _read_json(path: Path) -> dict | None:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def _joint_play(backlash: dict, kind: str) -> str:
    """Sum of the mid-tolerance plays of the stack's joints of one kind ("D fit" when the
    design.json predates joint kinds)."""
    joints = [j for j in backlash.get("d_joints", []) if j.get("kind", "D fit") == kind]
    return _n(sum(j.get("mid", 0.0) for j in joints)) if joints else "–"


def _n(v, digits: int = 4) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    return f"{v:.{digits}g}" if isinstance(v, (int, float)) else html.escape(str(v))


def verdict(build: dict, fea: dict | None) -> tuple[bool, list[str]]:
    """Released or not, and why: the release gate's verdict in ``build.json`` (the one
    stamped on the drawings) when it has one.

    Returns:
        (released, reasons): the reasons explain a refusal (or list caveats).
    """
    rel = build.get("release")
    if isinstance(rel, dict) and "released" in rel:  # the release gate's verdict, as stamped
        return bool(rel["released"]), [str(r) for r in rel.get("reasons", [])]
    if isinstance(build.get("verdict"), (str, dict)):
        v = build["verdict"]
        status = v if isinstance(v, str) else str(v.get("status", ""))
        reasons = list(build.get("reasons") or (v.get("reasons", []) if isinstance(v, dict) else []))
        return status.lower().startswith("released"), [str(r) for r in reasons]
    reasons = []
    ver = build.get("verification")
    if not isinstance(ver, dict):
        reasons.append(f"not FEA-verified (built with {written('verify', False)}): the parts "
                       "are beam-theory designs")
    elif not ver.get("ok", False):
        reasons.append("FEA verification failed")
    if fea is not None:
        reasons += [str(f) for f in fea.get("failures", [])]
    checks = build.get("checks", {})
    if not checks.get("passed", True):
        reasons.append(f"{checks.get('n_failed', '?')} check(s) failed")
    if checks.get("violations_accepted"):
        reasons.append("manufacturability violations were accepted "
                       f"({written('accept_violations', True)})")
    return not reasons, reasons


def _duty(design: dict, fea: dict | None, name: str) -> dict | None:
    """A spring's duty entry: the verified one (fea.json) when there is one."""
    f = ((fea or {}).get("springs", {}).get(name) or {}).get("duty")
    return f or (design.get("springs", {}).get(name) or {}).get("duty")


def caveats(design: dict, fea: dict | None) -> list[str]:
    """What a reader must know even of a released build: what each spring is rated for."""
    out = []
    for n in design.get("springs", {}):
        d = _duty(design, fea, n)
        if d:
            out.append(f"spring {n}: {d['rating']} (at the {d['where']})")
    return out


def _verdict_html(build: dict, fea: dict | None, design: dict) -> str:
    released, reasons = verdict(build, fea)
    head = ("Released for manufacture" if released else "Not for manufacture")
    items = "".join(f"<li>{html.escape(r)}</li>" for r in reasons)
    extra = (build.get("release") or {}).get("notes", []) if isinstance(build.get("release"), dict) else []
    rated = "".join(f"<li>{html.escape(str(c))}</li>" for c in caveats(design, fea))
    notes = "".join(f"<li>{html.escape(str(c))}</li>" for c in extra)
    # the rating is what the parts are rated for, released or not: neither a reason nor a caveat
    return (f"<h2>Verdict</h2><div class='verdict {'ok' if released else 'bad'}'>{head}</div>"
            + (f"<p>Why not:</p><ul>{items}</ul>" if items else "")
            + (f"<p>Rated for (not a reason):</p><ul>{rated}</ul>" if rated else "")
            + (f"<p>Notes (do not stop the release):</p><ul>{notes}</ul>" if notes else ""))


def _life_at_max(s: dict, f: dict):
    """A spring's life at ±θmax for the table: cycles, the words for an infinite life (JSON
    null), or None without a duty."""
    d = f.get("duty") or s.get("duty")
    if not d:
        return None
    life = d.get("life_at_max_deflection_cycles")
    return "no failure (below the endurance limit)" if life is None else life


def _spec_rows(design: dict, fea: dict | None) -> str:
    """The spec vs achieved table: one column per spring plus the stack."""
    springs = design.get("springs", {})
    fsp = (fea or {}).get("springs", {})
    header = "<tr><th>quantity</th>" + "".join(f"<th>{html.escape(n)}</th>" for n in springs) + "</tr>"

    def row(label, fn, digits=4, flag=None):
        cells = []
        for n, s in springs.items():
            f = fsp.get(n, {})
            v = fn(s, f)
            bad = flag is not None and v is not None and flag(v, s, f)
            cells.append(f"<td class='n{' fail' if bad else ''}'>{_n(v, digits)}</td>")
        return f"<tr><td>{html.escape(label)}</td>{''.join(cells)}</tr>"

    def duty_value(key):
        def get(s, f):
            d = f.get("duty") or s.get("duty")
            return None if not d else d.get(key)
        return get

    rows = [
        row("K target (N·m/rad)", lambda s, f: s.get("target_stiffness_Nm_per_rad")),
        row("K beam theory (N·m/rad)", lambda s, f: s.get("stiffness_Nm_per_rad")),
        row("K FEA (N·m/rad)", lambda s, f: f.get("stiffness_fea_Nm_per_rad")),
        row("FEA error vs target (%)", lambda s, f: f.get("error_vs_target_pct"), 3,
            lambda v, s, f: abs(v) > f.get("tolerance_pct", 1.0)),
        row("discretisation error (%)", lambda s, f: f.get("discretisation_error_pct"), 3),
        row("peak stress, design prediction (MPa)", lambda s, f: s.get("peak_stress_predicted_MPa"), 4),
        row("peak stress, FEA (MPa)", lambda s, f: f.get("peak_von_mises_MPa"), 4),
        row("yield margin (FEA, else design)",
            lambda s, f: f.get("yield_margin", s.get("yield_margin")), 3,
            lambda v, s, f: v < s.get("required_yield_margin", 1.0)),
        row("required yield margin", lambda s, f: s.get("required_yield_margin"), 3),
        row("yield margin the design sized to (with a declared duty)",
            lambda s, f: s.get("required_yield_margin_with_duty"), 3),
        row("duty: Miner sum", duty_value("miner_sum"), 3),
        row("duty: fatigue safety factor", duty_value("safety_factor"), 3,
            lambda v, s, f: v < (f.get("duty") or s.get("duty"))["required_safety_factor"]),
        row("life at ±θmax (cycles)", _life_at_max, 3),
        row("fatigue-rated deflection (°)", duty_value("fatigue_rated_deflection_deg"), 3),
        row("deflection limit (rad)", lambda s, f: s.get("max_deflection_rad")),
        row("flexures", lambda s, f: s.get("n_flexures")),
        row("disk thickness (mm)", lambda s, f: s.get("thickness_mm")),
        row("contact radius r_c (mm)", lambda s, f: s.get("contact_radius_mm"), 4),
        row("mass (kg)", lambda s, f: s.get("mass_kg")),
        row("energy density (J/cm³)", lambda s, f: s.get("energy_density_J_per_cm3")),
    ]
    st = design.get("stack", {})
    b = st.get("backlash_rad", {})
    tot = b.get("with_d_joints", {})
    fst = (fea or {}).get("stack", {})
    stack_rows = [
        ("sequence", " + ".join(st.get("sequence", []))),
        ("K target (N·m/rad)", _n(st.get("target_stiffness_Nm_per_rad"))),
        ("K beam theory (N·m/rad)", _n(st.get("stiffness_Nm_per_rad"))),
        ("K FEA (N·m/rad)", _n(fst.get("stiffness_fea_Nm_per_rad"))),
        ("deflection limit of the stack (rad; paper eq. 10: the first spring to reach its "
         "own limit)", _n(st.get("max_deflection_rad"))),
        ("limiting spring", html.escape(str(st.get("limiting_spring", "–")))),
        ("cam backlash nominal (rad; paper eqs. 1-3)", _n(b.get("nominal"))),
        ("cam backlash worst case (rad; below 0: the tolerances allow a preloaded, "
         "interfering cam)", f"{_n(b.get('worst_min'))} … {_n(b.get('worst_max'))}"),
        ("cam backlash RSS (rad; root sum square of the tolerances; below 0: a stack of "
         "usual parts can preload a cam)", f"{_n(b.get('rss_min'))} … {_n(b.get('rss_max'))}"),
        ("D-fit play of the torque shafts (rad, mid-tolerance, all D joints)",
         _joint_play(b, "D fit")),
        ("rim pin play (rad, mid-tolerance, all dowelled rim joints: E7/m6 slip fits)",
         _joint_play(b, "rim pins")),
        ("stack backlash input to output, cams + D fits + rim pins (rad): nominal; worst case",
         f"{_n(tot.get('nominal'))}; {_n(tot.get('worst_min'))} … {_n(tot.get('worst_max'))}"
         if tot else "–"),
        ("mass (kg)", _n(st.get("mass_kg"))),
        ("energy density (J/cm³)", _n(st.get("energy_density_J_per_cm3"))),
        ("specific energy (J/kg)", _n(st.get("specific_energy_J_per_kg"))),
    ]
    stack_html = "".join(f"<tr><td>{html.escape(k)}</td><td class='n'>{v}</td></tr>"
                         for k, v in stack_rows)
    return (f"<h2>Spec vs achieved</h2><h3>Springs</h3><table>{header}{''.join(rows)}</table>"
            f"<h3>Stack</h3><table><tr><th>quantity</th><th>value</th></tr>{stack_html}</table>")


def _duty_html(out: Path, design: dict, fea: dict | None) -> str:
    """The duty, the damage per block, the life at ±θmax, the fatigue-rated deflection, and
    the Haigh and S-N plots of every spring."""
    from springcad.report.duty_png import duty_rows

    parts = []
    for n in design.get("springs", {}):
        d = _duty(design, fea, n)
        if not d:
            parts.append(f"<h3>{html.escape(n)}</h3><p>duty not checked: no fatigue data for "
                         "this material</p>")
            continue
        rows = "".join(f"<tr><td>{html.escape(k)}</td><td>{html.escape(v)}</td></tr>"
                       for k, v in duty_rows(d))
        figs = _figures([(out / "fea" / f"{n}_haigh.png", f"{n}: Haigh diagram"),
                         (out / "fea" / f"{n}_sn.png", f"{n}: S-N and the duty")], 520)
        cf = ((fea or {}).get("springs", {}).get(n) or {}).get("contact_fatigue")
        contact = (f"<p>Contact at the ball: {html.escape(cf['text'])}</p>" if cf else "")
        parts.append(f"<h3>{html.escape(n)}</h3><table>{rows}</table>{contact}{figs}")
    return "<h2>Duty</h2>" + "".join(parts)


def _warnings_html(design: dict, fea: dict | None, build: dict) -> str:
    items = list(design.get("warnings", [])) + list(design.get("notes", []))
    if fea is not None:
        items += list(fea.get("notes", []))
        for n, s in fea.get("springs", {}).items():
            for flag in (s.get("contact_sweep") or {}).get("flags", []):
                items.append(f"contact {n}: {flag.get('message', flag)}")
    items += [f"{c.get('subject', '')}: {c.get('name', '')}: {c.get('message', '')}"
              for c in build.get("checks", {}).get("items", []) if not c.get("passed", True)]
    body = ("".join(f"<li>{html.escape(str(w))}</li>" for w in items) if items
            else "<li>none</li>")
    return f"<h2>Warnings</h2><ul>{body}</ul>"


def _figures(paths: list[tuple[Path, str]], width: int) -> str:
    figs = [f"<figure>{_img(p, cap, width=width)}<figcaption>{html.escape(cap)}</figcaption></figure>"
            for p, cap in paths if p.is_file()]
    return (f"<p class='narrow'>{NARROW_NOTE}</p><div class='figs'>{''.join(figs)}</div>"
            if figs else "<p>no images in this build</p>")


def _fea_html(out: Path, design: dict) -> str:
    imgs = []
    for n in design.get("springs", {}):
        imgs += [(out / "fea" / f"{n}_von_mises.png", f"{n}: von Mises stress at the max deflection"),
                 (out / "fea" / f"{n}_von_mises_peak.png", f"{n}: at the peak"),
                 ]
    contact = [(out / "fea" / f"{n}_contact.png", f"{n}: cam contact sweep over ±θmax")
               for n in design.get("springs", {})]
    if not any(p.is_file() for p, _ in imgs + contact):
        return ("<h2>FEA</h2><p>no FEA images in this build (not verified, or "
                f"{written('render', False)})</p>")
    has_contact = any(p.is_file() for p, _ in contact)  # no contact sweep: no empty block
    return "<h2>FEA</h2>" + _figures(imgs, 520) + (_figures(contact, 1050) if has_contact else "")


def _drawings_html(out: Path) -> str:
    cells = []
    for svg in sorted((out / "parts").glob("*.svg")):
        pdf = svg.with_suffix(".pdf")
        thumb = _img(svg, f"drawing {svg.stem}", cls="thumb")
        link = (f"<a href='parts/{html.escape(pdf.name)}'>{thumb}</a>" if pdf.is_file() else thumb)
        cells.append(f"<figure>{link}<figcaption>{html.escape(svg.stem)}"
                     f"{' (PDF)' if pdf.is_file() else ''}</figcaption></figure>")
    return "<h2>Drawings</h2>" + (f"<div class='figs'>{''.join(cells)}</div>" if cells
                                  else "<p>no drawings in this build</p>")


#: BOM columns the report shows: (heading, CSV column(s)); the CSV keeps every column
BOM_VIEW = (("item", ("item",)), ("part number", ("part_number",)), ("name", ("name",)),
            ("part", ("title",)), ("qty", ("quantity",)), ("make / buy", ("make_or_buy",)),
            ("process", ("process",)), ("material", ("material",)),
            ("standard", ("standard",)), ("t / L (mm)", ("thickness_or_length_mm",)),
            ("mass each / total (g)", ("mass_each_g", "mass_total_g")))
#: numeric BOM columns (right-aligned)
_BOM_NUMERIC = {"item", "qty", "t / L (mm)", "mass each / total (g)"}


def _bom_files(files: str) -> str:
    """The part's files as links named by their kind (STEP, DXF, PDF...), PDF first."""
    order = {".pdf": 0, ".dxf": 1, ".step": 2, ".stl": 3, ".svg": 4}
    paths = sorted(files.split(), key=lambda f: order.get(Path(f).suffix, 9))
    return " ".join(f"<a href='{html.escape(f)}'>{html.escape(Path(f).suffix[1:].upper())}</a>"
                    for f in paths)


def _bom_html(out: Path) -> str:
    """The BOM as a person reads it: the columns needed to order and make, files as links
    (the full table is ``bom.csv``)."""
    path = out / "bom.csv"
    if not path.is_file():
        return "<h2>Bill of materials</h2><p>no bom.csv in this build</p>"
    rows = list(csv.DictReader(io.StringIO(path.read_text(encoding="utf-8"))))
    head = "".join(f"<th>{html.escape(h)}</th>" for h, _ in BOM_VIEW) + "<th>files</th>"
    body = []
    for r in rows:
        cells = []
        for h, cols in BOM_VIEW:
            text = " / ".join(r.get(c, "") for c in cols if r.get(c, ""))
            cls = " class='n'" if h in _BOM_NUMERIC else ""
            cells.append(f"<td{cls}>{html.escape(text)}</td>")
        cells.append(f"<td>{_bom_files(r.get('files', ''))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return ("<h2>Bill of materials</h2><p><a href='bom.csv'>bom.csv</a> holds every column "
            "(kind, instances); parts to make are in <a href='vendor.zip'>vendor.zip</a>.</p>"
            f"<div class='scroll'><table class='bom'><tr>{head}</tr>{''.join(body)}</table></div>")


def _axial_location(design: dict, text) -> str:
    """``text(end_hubs, flanges)`` (:func:`springcad.export.vendor.axial_location`) for the
    stack of a design.json."""
    comps = design.get("stack", {}).get("components", [])
    hubs = any(c.get("kind") == "camshaft" and c.get("dims", {}).get("hub_length_mm", 0) > 0
               for c in comps)
    return text(hubs, any(c.get("kind") == "rim_flange" for c in comps))


def render_build_report(out_dir: Path | str) -> str:
    """The HTML text of a build folder's report (see the module docstring)."""
    # here, not at the top: springcad.export pulls numpy, and importing springcad is light
    from springcad.export.vendor import AXIAL_LOCATION_TITLE, axial_location

    out = Path(out_dir)
    design = _read_json(out / "design.json") or {}
    fea = _read_json(out / "fea" / "fea.json")
    build = _read_json(out / "build.json") or {}
    job = design.get("job", {}).get("name") or build.get("job", {}).get("name", out.name)
    meta = (f"springcad {html.escape(str(build.get('springcad_version', design.get('springcad_version', ''))))}"
            f", built {html.escape(str(build.get('started', '')))}, config "
            f"{html.escape(str(build.get('job', {}).get('config', design.get('job', {}).get('config', ''))))}")
    parts = [
        f"<h1>Build report: {html.escape(job)}</h1><p>{meta}</p>",
        _verdict_html(build, fea, design),
        _spec_rows(design, fea),
        _duty_html(out, design, fea),
        _warnings_html(design, fea, build),
        _fea_html(out, design),
        "<h2>Assembly</h2>" + _figures([(out / "assembly.png", "assembly render")], 700)
        + f"<p><b>{AXIAL_LOCATION_TITLE}:</b> "
        f"{html.escape(_axial_location(design, axial_location))}</p>",
        _drawings_html(out),
        _bom_html(out),
    ]
    return page(f"springcad build report: {job}", "\n".join(parts))


def write_build_report(out_dir: Path | str) -> Path:
    """Write ``report.html`` into a build folder and return its path."""
    path = Path(out_dir) / "report.html"
    path.write_text(render_build_report(out_dir), encoding="utf-8")
    return path
