"""Write the paper validation report: validation.json, validation.md and a plot."""

from __future__ import annotations

from pathlib import Path

from springcad.report.html_page import markdown_html, page
from springcad.report.jsonio import write_json


#: below this max/min ratio of the stiffness range the axes are linear with plain ticks
LOG_AXES_RATIO = 10.0
#: distance of a point's label from the diagonal side of the point (px at the figure's dpi)
LABEL_OFFSET_PX = 28.0


def plot_predicted_vs_measured(v, path: Path) -> None:
    """Predicted (before/after) vs measured stiffness, one point per configuration."""
    fig = predicted_vs_measured_figure(v.configurations)
    fig.savefig(path, dpi=130)
    import matplotlib.pyplot as plt

    plt.close(fig)


def predicted_vs_measured_figure(configurations):
    """The figure of :func:`plot_predicted_vs_measured` (matplotlib, Agg).

    Args:
        configurations: objects with ``configuration``, ``measured_stiffness_Nm_per_rad``,
            ``target_stiffness_Nm_per_rad`` and ``predicted_stiffness_after_Nm_per_rad``.

    Returns:
        The figure; its axes carry the configuration labels as ``ax.texts``
        (placed by :func:`place_diagonal_labels`, so no two overlap).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    fig, ax = plt.subplots(figsize=(6, 5.5), dpi=130)
    meas = [c.measured_stiffness_Nm_per_rad for c in configurations]
    before = [c.target_stiffness_Nm_per_rad for c in configurations]
    after = [c.predicted_stiffness_after_Nm_per_rad for c in configurations]
    ax.plot(meas, before, "o", mfc="none", label="before: design target", zorder=3)
    ax.plot(meas, after, "s", label="after: enriched model (leave-one-out)", zorder=3)
    values = meas + before + after
    lo, hi = min(values), max(values)
    log = hi / lo >= LOG_AXES_RATIO
    if log:
        lim = [lo / 1.25, hi * 1.1]
        ax.set_xscale("log")
        ax.set_yscale("log")
        for axis in (ax.xaxis, ax.yaxis):  # plain numbers (30, 100), not 3x10^1
            axis.set_major_formatter(ScalarFormatter())
            axis.set_minor_formatter(NullFormatter())
    else:
        pad = 0.08 * (hi - lo)
        lim = [max(0.0, lo - 2.0 * pad), hi + pad]
    ax.plot(lim, lim, "k-", lw=0.8, label="predicted = measured", zorder=2)
    ax.set_xlim(lim)
    ax.set_ylim(lim)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("measured stiffness (N·m/rad)")
    ax.set_ylabel("predicted stiffness (N·m/rad)")
    ax.set_title("Paper Table I: predicted vs measured")
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(True, which="major", lw=0.3)
    fig.tight_layout()
    anchors = [(m, min(b, a)) for m, b, a in zip(meas, before, after)]
    place_diagonal_labels(ax, anchors, [c.configuration for c in configurations])
    return fig


def place_diagonal_labels(ax, anchors, labels, offset_px: float = LABEL_OFFSET_PX,
                          fontsize: float = 7.5, pad_px: float = 3.0) -> list:
    """Label points that lie near the diagonal without collisions (a 1D label adjuster).

    Each label sits below-right of its point, ``offset_px`` from it across the
    diagonal (the side where the points leave room), with a leader line. Taken
    from the lower left up, each label slides up along the diagonal until its
    box clears every label placed before by ``pad_px``; then all slide back by
    their mean shift, which keeps every clearance.

    Args:
        ax: the axes (limits and layout final).
        anchors: (x, y) data points, one per label.
        labels: the texts.
        offset_px: distance across the diagonal (px).
        fontsize: label size (pt).
        pad_px: clearance between boxes (px).

    Returns:
        The annotation artists, in the order of ``labels``.
    """
    import numpy as np

    fig = ax.figure
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    to_px = ax.transData
    pts = to_px.transform(np.asarray(anchors, dtype=float))
    u = np.array([1.0, 1.0]) / np.sqrt(2.0)   # along the diagonal
    n = np.array([1.0, -1.0]) / np.sqrt(2.0)  # across it, toward the lower right
    sizes = []
    for text in labels:  # measure each label's box at its font size
        t = ax.text(0, 0, text, fontsize=fontsize)
        box = t.get_window_extent(renderer)
        sizes.append((box.width + pad_px, box.height + pad_px))
        t.remove()
    s = pts @ u
    across = pts @ n + offset_px

    def corner(i, along):  # top-left corner of label i (px)
        return along * u + across[i] * n

    def overlaps(i, j, along_i, along_j) -> bool:
        (xi, yi), (xj, yj) = corner(i, along_i), corner(j, along_j)
        return (xi < xj + sizes[j][0] and xj < xi + sizes[i][0]
                and yi - sizes[i][1] < yj and yj - sizes[j][1] < yi)

    placed = s.copy()
    done = []
    step = 0.25 * min(h for _, h in sizes)
    for i in np.argsort(s, kind="stable"):  # bottom-left first; push each up the diagonal
        while any(overlaps(i, j, placed[i], placed[j]) for j in done):
            placed[i] += step
        done.append(i)
    placed -= (placed - s).mean()  # a common shift keeps every clearance
    out = []
    inv = to_px.inverted()
    for i, text in enumerate(labels):
        xytext = inv.transform(corner(i, placed[i]))
        out.append(ax.annotate(
            text, xy=anchors[i], xytext=xytext, textcoords="data", fontsize=fontsize,
            ha="left", va="top",
            arrowprops={"arrowstyle": "-", "lw": 0.5, "color": "0.4", "shrinkA": 0,
                        "shrinkB": 3}))
    return out


def markdown(v) -> str:
    d = v.to_dict()
    s = d["summary"]
    lines = [
        "# springcad validation against the paper",
        "",
        "## Verdict",
        "",
        f"Stiffness of the seven Table I configurations: mean |error| "
        f"**{s['mean_abs_error_before_pct']:.2f} % before** (design target), "
        f"**{s['mean_abs_error_after_pct']:.2f} % after** (enriched model, leave-one-out); "
        f"worst {s['worst_abs_error_before_pct']:.2f} % -> {s['worst_abs_error_after_pct']:.2f} %.",
        "",
        "Every predicted number comes from springcad's design, tolerance"
        + (" and FEA" if any(m.source != "beam" for m in v.springs.values()) else "")
        + " models run on the paper templates; only the *measured* columns come from the "
          "paper's Tables I and II.",
        "",
        "## Assumptions the paper leaves open",
        "",
        "| quantity | value | source |",
        "|---|---|---|",
        "| N, tip radius, contact radius | 28, 0.300 mm, 5.5 mm (S1 and S2) | paper Section II-C and shared/data README |",
        "| outer radius | 33.5 mm | shared/notes/design-method.md check value (not in the paper) |",
        "| thickness | 4.5 mm | design-method.md check value (not in the paper) |",
        "| design stress | 912 MPa | design-method.md check value (not in the paper) |",
        "| root radius | rim rule, R_o - R_r = (2 pi R_r/N - w0)/1.5 | reference tool's rule (design-method.md eq. 8) |",
        "| material | 420 hardened, E 200 GPa, nu 0.28, yield 1344 MPa, 7740 kg/m³ | AK Steel 420 data sheet |",
        "| tip-to-cam gap | 0.025 mm per side | paper Section II-B |",
        "| tolerances (Table I) | Mfr. 2: t_shaft 0.02 mm, t_spring 0.05 mm | paper Table II |",
        "",
        "## Stiffness (N·m/rad)",
        "",
        f"| configuration | measured | target (before) | beam | "
        f"{'FEA of the design' if any(m.source != 'beam' for m in v.springs.values()) else 'beam (no FEA run)'}"
        " | after (LOO) "
        "| error before | error after |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for c in v.configurations:
        lines.append(f"| {c.configuration} | {c.measured_stiffness_Nm_per_rad:.2f} "
                     f"| {c.target_stiffness_Nm_per_rad:.2f} "
                     f"| {c.beam_stiffness_Nm_per_rad:.2f} | {c.geometry_stiffness_Nm_per_rad:.2f} "
                     f"| {c.predicted_stiffness_after_Nm_per_rad:.2f} "
                     f"| {c.error_before_pct:+.2f} % "
                     f"| {c.error_after_pct:+.2f} % |")
    lines += [
        "",
        f"Mean absolute error: **{s['mean_abs_error_before_pct']:.2f} % before**, "
        f"**{s['mean_abs_error_after_pct']:.2f} % after** (worst {s['worst_abs_error_before_pct']:.2f} % "
        f"-> {s['worst_abs_error_after_pct']:.2f} %). The after-error is out of sample: each "
        "configuration is predicted with the width offset fitted on the other six. Error = "
        "(predicted - measured) / measured.",
        "",
        "![predicted vs measured](predicted_vs_measured.png)",
        "",
        "## What each effect contributes (per spring)",
        "",
        "| effect | spring | change of K | added | how |",
        "|---|---|---|---|---|",
    ]
    for e in d["effects"]:
        if e["effect"] == "width_offset":
            change = (f"{e['sensitivity_pct_per_0.01mm']:+.2f} % per +0.01 mm; "
                      f"[{e['range_pct_at_t_spring'][0]:+.1f}, {e['range_pct_at_t_spring'][1]:+.1f}] % "
                      f"at ±t_spring = {e['t_spring_mm']} mm; {e['change_pct']:+.2f} % at the "
                      f"fitted {e['fitted_offset_mm_in_sample']:.4f} mm")
        elif e["effect"] == "youngs_modulus":
            change = f"[{e['range_pct'][0]:+.1f}, {e['range_pct'][1]:+.1f}] %"
        else:
            change = f"{e['change_pct']:+.2f} %"
        lines.append(f"| {e['effect']} | {e['spring']} | {change} | {'yes' if e['added'] else 'no'} "
                     f"| {e['how']} |")
    resid = [c.error_after_pct for c in v.configurations]
    lines += [
        "",
        "### What remains unexplained",
        "",
        f"After the added effects the residual ranges {min(resid):+.2f} % to {max(resid):+.2f} %. "
        "A single width offset cannot make S2 (measured +14.8 % over target) and S1 (+7.4 %) stiffer "
        "by the measured ratio with one value; spring-to-spring scatter of the physical parts "
        "(each configuration reuses a different subset of four S1 and two S2) is not in any model "
        "here and is the likely remainder.",
        "",
        "## Deflection limits (eq. 10)",
        "",
        "| configuration | eq. 10 (rad) | Table I (rad) | agrees |",
        "|---|---|---|---|",
    ]
    for c in v.configurations:
        ok = abs(c.deflection_limit_rad - c.table_deflection_limit_rad) < 1e-3
        lines.append(f"| {c.configuration} | {c.deflection_limit_rad:.3f} "
                     f"| {c.table_deflection_limit_rad:.3f} | {'yes' if ok else '**no**'} |")
    lines += ["", *[f"- {n}" for n in d["notes"]], "",
              "## Backlash (rad): measured vs the tolerance range (per-interface range x interfaces)",
              "", "| configuration | nominal | worst min | worst max | measured | where |",
              "|---|---|---|---|---|---|"]
    for c in v.configurations:
        lo, hi = c.predicted_backlash_range_rad
        lines.append(f"| {c.configuration} | {c.nominal_backlash_rad:.4f} | {lo:.4f} | {hi:.4f} "
                     f"| {c.measured_backlash_rad:.4f} | {c.backlash_position} |")
    lines += ["", "Manufacturer comparison (4xS1, Table II):", "",
              "| manufacturer | t_shaft | t_spring | backlash worst max | measured | where "
              "| K range at ±t_spring | measured K | where |",
              "|---|---|---|---|---|---|---|---|---|"]
    for m in d["manufacturers"]:
        lo, hi = m["predicted_stiffness_range_at_t_spring"]
        lines.append(f"| {m['manufacturer']} | {m['t_shaft_mm']} | {m['t_spring_mm']} "
                     f"| {m['predicted_backlash_range_rad'][1]:.4f} | {m['measured_backlash_rad']:.4f} "
                     f"| {m['backlash_position']} | [{lo:.2f}, {hi:.2f}] | {m['measured_stiffness']:.2f} "
                     f"| {m['stiffness_position']} |")
    lines += _geometry_change_lines(v.geometry_changes)
    lines += ["", "## Energy", "", "| configuration | J/cm³ | J/kg |", "|---|---|---|"]
    for c in v.configurations:
        lines.append(f"| {c.configuration} | {c.energy_density_J_per_cm3:.3f} "
                     f"| {c.specific_energy_J_per_kg:.1f} |")
    lines += ["", "The paper reports 0.24-0.39 J/cm³ and 31-52 J/kg for its series stacks "
              "(measured hardware, thick bolted rims)."]
    return "\n".join(lines) + "\n"


def _geometry_change_lines(changes: list[dict]) -> list[str]:
    """Markdown: springcad's geometry against the reference tool's, per paper spring."""
    if not changes:
        return []
    fea = "peak_fea_2d_MPa" in changes[0]["reference"]
    lines = ["", "## What springcad changed against the reference geometry", "",
             "The reference tool balances each serpentine so that its root sits on the tip's "
             "radial line, draws a plain circular root fillet and sizes the flexures to the "
             "design stress as a beam. springcad makes two changes. (1) The serpentine's tilt "
             "amplitude is ramped along the flexure so that a tangential tip load moves the ball "
             "tangentially only (balance \"uncoupled\"): with the reference balance the ball "
             "climbs the cam flank one way and sinks into the pocket the other, and the "
             "small-angle stiffness of the cam contact departs from the linear one. (2) A root "
             "flare (the flexure widens smoothly over the last part before the rim), chosen by "
             "the FEA-calibrated stress model. The widths are rescaled so the beam stiffness "
             "is unchanged; the beam stress would be lowered too if the predicted peak still "
             "missed the required yield margin.", "",
             "| spring | geometry | serpentine | root flare | beam K N·m/rad | nominal beam MPa "
             "| predicted peak MPa | yield margin | mass g |"
             + (" FEA 2D K N·m/rad | FEA 2D peak MPa | FEA margin |" if fea else ""),
             "|---|---|---|---|---|---|---|---|---|" + ("---|---|---|" if fea else "")]
    for c in changes:
        for tag in ("reference", "springcad"):
            g = c[tag]
            flare = "0" if tag == "reference" else f"{c['root_flare']:g} over {c['root_flare_length_mm']:.2f} mm"
            row = (f"| {c['spring']} | {tag} | {g.get('serpentine_balance') or g.get('flexure', 'straight')} "
                   f"| {flare} | {g['beam_stiffness_Nm_per_rad']:.2f} "
                   f"| {g['nominal_beam_stress_MPa']:.0f} | {g['predicted_peak_MPa']:.0f} "
                   f"({g['predicted_region']}) | {g['yield_margin_predicted']:.3f} | {g['mass_g']:.2f} |")
            if fea:
                row += (f" {g['stiffness_fea_2d_Nm_per_rad']:.2f} | {g['peak_fea_2d_MPa']:.0f} "
                        f"({g['peak_fea_2d_region']}) | {g['yield_margin_fea_2d']:.3f} |")
            lines.append(row)
    return lines


def write_paper_report(v, out_dir: Path) -> list[Path]:
    """Write ``validation.json``, the plot, ``validation.md`` and ``report.html``.

    ``report.html`` is the Markdown report as one self-contained page (the plot inlined).
    """
    out_dir = Path(out_dir)
    write_json(out_dir / "validation.json", v.to_dict())
    plot_predicted_vs_measured(v, out_dir / "predicted_vs_measured.png")
    md = markdown(v)
    (out_dir / "validation.md").write_text(md, encoding="utf-8")
    (out_dir / "report.html").write_text(
        page("springcad validation against the paper", markdown_html(md, out_dir)),
        encoding="utf-8")
    return [out_dir / n for n in ("validation.json", "predicted_vs_measured.png",
                                  "validation.md", "report.html")]
